#pragma once
// Issue 8: "the closure reproduces the coarse-grained DEM flow of the platform box (free-surface angle
// and surface speed over a cycle) - report the error - before it is trusted at large scale".
//
// The DEM side: a `grainscale cg` fields.h5 with one frame per snapshot on an (x, z) grid in the box's
// own frame (docs/coarsegrain_layout.md). Per frame, the free-surface height per column (the cg
// `surface_height` field) gives the surface's slope in the box frame by least squares over the columns
// that hold grain; with the box's tilt θ(t) from the DEM scenario's motion that is the free-surface
// angle to the horizontal, β_h = θ + atan(dh/dx). The surface speed is the mass-weighted mean of u_x
// over the cells within `measure_depth` (default: the closure's flowing-layer depth ℓ) of each
// column's surface, averaged over the columns.
// The closure side: ShallowGranularFlow (continuum/closure/) on the same box, pivot and motion, filled
// to the DEM's mean surface height at the first compared frame, with the bed friction of a listed hold
// scenario; the same two measures from its h(x) and u_s(x) (the surface speed is the mean over the
// same depth of u_s e^{-ζ/ℓ}, as the DEM's). Errors: RMS and max over the frames.
// The DEM box has side walls: the closure is run with their friction μ_w a/W (side_wall_friction.hpp,
// Jop, Forterre & Pouliquen 2005), W the box's width across the section (the cg grid's y extent) and
// μ_w the DEM's sliding friction of the grain on the box's material; and, for comparison, without
// them (the 2-D closure, `open_*`). The verdict is the one with the side walls.
// Beside them, the null model of a bed that does not move (`still_*`): the bar means something only
// where that fails it.
// "Agrees" (this study's bar, not a published one): surface angle within kAngleTolerance RMS and
// surface speed within kSpeedTolerance of the DEM's RMS surface speed (at least kSpeedFloor) RMS.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "studies/closure_friction_fit.hpp"
#include "studies/hold_settings.hpp"

namespace grainscale::studies {

struct ClosureDemComparison {
  std::string cg_fields, dem_scenario, material_from;
  double box_length = 0, fill_height = 0, flowing_layer = 0;  // [m]
  double measure_depth = 0;  // the surface speed is averaged over min(this, h) below the surface [m]
  std::vector<double> times;                            // compared frames [s]
  std::vector<double> tilt_deg;                         // the box's tilt [deg]
  std::vector<double> dem_angle_deg, closure_angle_deg; // free-surface angle to the horizontal [deg]
  std::vector<double> dem_speed, closure_speed;         // surface speed along the box [m/s]
  std::vector<double> open_angle_deg, open_speed;       // the closure without side walls
  std::vector<std::vector<double>> closure_depth;       // h at the cell centres per frame (side walls) [m]
  double side_wall_width = 0, side_wall_friction = NAN; // W [m] and μ_w used
  double angle_rms_error_deg = 0, angle_max_error_deg = 0;
  double speed_rms_error = 0, speed_max_error = 0, dem_speed_rms = 0;
  double open_angle_rms_error_deg = 0, open_angle_max_error_deg = 0, open_speed_rms_error = 0, open_speed_max_error = 0;
  /// The null model: the bed of the first frame held rigid in the box (surface angle tilt − its
  /// initial slope, speed 0). A closure that does no better than this has not shown what it adds.
  double still_angle_rms_error_deg = 0, still_speed_rms_error = 0;
  bool still_agrees = false;  // the null model passes the bar (on all frames)
  bool agrees = false;
  std::optional<ClosureFit> fit;     // when asked for
  std::vector<std::string> figures;  // written into the folder given (with comparison.csv), names relative to it
  std::vector<std::string> notes;    // what limits the comparison
};

/// Throws InputError naming the file for a fields file without surface heights or velocities, a
/// scenario without the container's motion or the grain-wall pair friction, or fewer than 2 frames
/// with grain; and, with a fit, an unknown parameter name, or a split that leaves fewer than 3 frames
/// on either side.
ClosureDemComparison compare_closure_with_dem(const std::string& cg_fields, const std::string& dem_scenario,
                                              const std::string& container, const HoldSettings& material,
                                              const std::string& folder,
                                              const std::optional<ClosureFitSettings>& fit = std::nullopt,
                                              double measure_depth = NAN);

}  // namespace grainscale::studies
