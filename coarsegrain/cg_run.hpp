#pragma once
// The coarse-graining run behind `grainscale cg`: snapshots in, fields and the report's measures out.
//
//   fields.h5 + fields.xmf   every output frame's fields (docs/coarsegrain_layout.md; ParaView: fields.xmf)
//   fields.csv               t_s,x_m,z_m,c,... per cell and frame (c: chaff volume concentration)
//   slices.csv               t_s,x_m,chaff_percent,... per snapshot and 50 mm slice (report Figure 11)
//   coverage.csv             t_s,x_m,coverage,... top-view chaff coverage per snapshot and slice
//   congregation.csv         t_s,index_left,index_right,... per snapshot
//   summary.yaml             settings used, kernel width, mass conservation, index statistics
#include <string>
#include <vector>

#include "coarsegrain/cg_settings.hpp"
#include "coarsegrain/congregation_index.hpp"

namespace grainscale::cg {

struct CgSummary {
  int snapshots = 0, frames = 0;
  double kernel_width = 0, true_diameter = 0;  // m
  double max_mass_error = 0;                   // largest |sum rho V - M| / M over snapshots
  std::vector<double> times;                   // of the snapshots
  std::vector<CongregationIndex> congregation; // per snapshot
  /// Things the fields are right by definition but perhaps not what was meant (e.g. a clump species
  /// without a density: its volume fraction counts the overlaps of its spheres).
  std::vector<std::string> warnings;
  std::string output_dir;
};

/// Run the coarse-graining described by `settings` and write its outputs into settings.output_dir
/// (created if missing). Throws InputError for bad input (a missing snapshot, an unknown wall or
/// material), std::runtime_error if an output cannot be written.
CgSummary run_coarse_graining(const CgSettings& settings);

}  // namespace grainscale::cg
