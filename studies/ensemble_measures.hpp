#pragma once
// What an ensemble measures in one run (DEM snapshots + their coarse-grained fields), so that
// variants can be compared over seeds (docs/studies.md, "Ensemble studies"):
//
//   congregation index per compartment: coarsegrain/congregation_index.hpp on each compartment's own
//       length (its own two ends, each `end_length` long), at the motion start and at the end; the
//       run's index is the mean over compartments of (left + right) / 2 (1: uniform). A split box's
//       compartments lie between its divider plates (box_mesh `compartments`, docs/walls_and_motion.md).
//   chaff per slice (report Figure 11): % of all chaff bodies per `slice_width` slice, start and end,
//       and each slice's chaff number fraction relative to the whole box's at the end (1: uniform).
//   bulk density of the settled bed at the motion start: the coarse-grained mass per unit floor area
//       over the bed height, summed over columns, sum_i sum_k rho_ik dz / sum_i h_i, where h_i is the
//       column's free surface: the height at which the solid fraction falls to half the column's
//       largest (linear between cell centres). The kernel is symmetric, so half its maximum marks the
//       mean surface (Weinhart et al. 2012).
//   surface-flow speed during the motion: per coarse-grained frame after the motion starts, the mean
//       over columns of |(u_x, u_z)| (relative to the container) in each column's highest cell with at
//       least half the column's largest solid fraction; the run's value is the mean over those frames.
#include <string>
#include <vector>

#include "coarsegrain/cg_settings.hpp"

namespace grainscale::studies {

struct CompartmentIndex {
  double x_lo = 0, x_hi = 0;  // m, container frame
  double left_start = 0, right_start = 0, left_end = 0, right_end = 0;
};

struct RunMeasures {
  double t_start = 0, t_end = 0;  // s: snapshots used as "motion start" and "end"
  int grain_bodies = 0, chaff_bodies = 0;  // at the end, inside the coarse-graining box
  std::vector<CompartmentIndex> compartments;
  double index_start = 0, index_end = 0;  // mean over compartments of the mean end index
  std::vector<double> slice_lo, slice_hi;  // m
  std::vector<double> chaff_percent_start, chaff_percent_end;
  std::vector<double> relative_chaff_end;  // slice chaff fraction / box chaff fraction (NaN: empty slice)
  double bulk_density = 0;   // kg/m^3, at the motion start
  double bed_height = 0;     // m, mean surface height at the motion start
  double surface_speed = 0;  // m/s, mean over the motion frames
  int motion_frames = 0;
};

/// Compartments of the container: `count` equal parts of [x_lo, x_hi].
std::vector<CompartmentIndex> equal_compartments(double x_lo, double x_hi, int count);

/// The container's compartments from a scenario: the wall named `wall` if it is a box_mesh (its
/// min.x, max.x, compartments), else one compartment over [x_lo, x_hi] (the coarse-graining box).
std::vector<CompartmentIndex> scenario_compartments(const std::string& scenario_file, const std::string& wall,
                                                    double x_lo, double x_hi);

/// Measures of one run: `snapshot_dir` (the DEM's snapshots), `cg` (the settings the run was
/// coarse-grained with, snapshot mode, 2-D grid) and its output folder (fields.csv). Throws
/// InputError when the run has no snapshot at or after `motion_from`.
RunMeasures measure_run(const std::string& snapshot_dir, const cg::CgSettings& cg, const std::string& cg_output,
                        double motion_from, std::vector<CompartmentIndex> compartments);

}  // namespace grainscale::studies
