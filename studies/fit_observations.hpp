#pragma once
// Measured or coarse-grained data for a continuum fit, moved onto the model's grid.
//
// Files use the layouts the stages share (docs/coarsegrain_layout.md):
//   fields    t_s,x_m,z_m,c[,sigma]       chaff volume concentration at points of the bed
//   coverage  t_s,x_m,coverage[,sigma]    top-view chaff coverage along the bed
// Other columns are ignored, so a `grainscale cg` fields.csv can be used as it is. Rows whose value
// is NaN carry no data (cells without particles) and are skipped.
//
// Each point goes to the nearest cell: the column whose x-range holds it, then the layer whose
// centre height in that column is closest (terrain-following cells), clamped to the bed. Coverage
// points go to the column holding x. Several points in one cell at one time are combined by their
// inverse-variance weighted mean, sigma = 1 / sqrt(sum 1/sigma_p^2), so a fine data grid counts as
// much as its information, not as its number of rows.
#include <optional>
#include <string>
#include <vector>

#include "continuum/grid.hpp"

namespace grainscale::studies {

struct ObservationFiles {
  std::string fields, coverage;                       // CSV paths; empty: not observed
  std::optional<double> field_sigma, coverage_sigma;  // for files without a sigma column
  /// Field rows whose solid volume fraction (column `phi`, as a `grainscale cg` fields.csv has)
  /// is below this are not data: above a bed's surface the kernel still sees a few grains, and c
  /// there is noise. 0: every row.
  double min_solid_fraction = 0;
  /// Rows (fields and coverage) before this time [s] are not data, e.g. the frame a model starts
  /// from (`initial: {type: file}`, docs/continuum.md) when the data file holds it too. 0: every row.
  double from = 0;
};

/// One value on the grid: a cell (fields) or a column (coverage) at one of the times.
struct Observation {
  std::size_t time = 0;   // index into Observations::times
  std::size_t index = 0;  // grid.index(i, k) for fields, column i for coverage
  double value = 0, sigma = 0;
  int points = 0;  // CSV rows combined into it
};

struct Observations {
  std::vector<double> times;  // increasing, all after t0: the union of the files' times
  std::vector<Observation> fields, coverage;
  std::size_t field_rows = 0, coverage_rows = 0;  // CSV rows used (finite values)
  /// Every row had a sigma (column or setting). If not, all rows weigh 1 and the fit's standard
  /// errors are scaled by chi2/dof (noise estimated from the scatter).
  bool sigma_known = true;
};

/// Read and map the files. InputError (file and line) for a missing column, a non-numeric value,
/// a point outside the bed by more than half a column (x) or a whole depth (z), sigma <= 0, a
/// time not after t0, or no data at all. With both files, each needs a sigma: their relative
/// weight depends on it.
Observations map_observations(const ObservationFiles& files, const continuum::Grid& grid, double t0);

}  // namespace grainscale::studies
