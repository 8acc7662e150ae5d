#pragma once
// Output of a continuum run (layout in docs/continuum.md, "Output"):
//   continuum.h5  — c(x, z, t) on the terrain-following grid, format "grainscale-continuum" v1;
//   slices.csv    — chaff per unit width in slices of fixed length along x, per output time;
//   coverage.csv  — top-view surface coverage (O1) per column, per output time.
// Every file is written to a temporary name and renamed into place.
#include <string>
#include <vector>

#include "continuum/model.hpp"
#include "continuum/observation.hpp"

namespace grainscale::continuum {

inline constexpr long kContinuumFormatVersion = 1;

struct RunRecord {
  std::vector<double> times;               // [s], including t = 0
  std::vector<std::vector<double>> fields; // c per time (cells)
  std::vector<Grid> grids = {};            // grid per time (moving surface); empty: model.grid() throughout
  const Grid& grid(const Model& model, std::size_t n) const { return grids.empty() ? model.grid() : grids[n]; }
};

void write_continuum_h5(const std::string& path, const Model& model, const SurfaceCoverage& observation,
                        const RunRecord& record);
/// Chaff [m²] (per unit width) in slices [j w, (j + 1) w) of x; cells are split by overlap length.
std::vector<double> chaff_per_slice(const Model& model, const std::vector<double>& c, double slice_width);
std::vector<double> chaff_per_slice(const Grid& grid, const std::vector<double>& c, double slice_width);
std::string slices_csv(const Model& model, const RunRecord& record, double slice_width);
std::string coverage_csv(const Model& model, const SurfaceCoverage& observation, const RunRecord& record);

}  // namespace grainscale::continuum
