#pragma once
// Issue 8: the flow closure's bed friction calibrated on coarse-grained DEM frames of a platform box,
// judged on later frames it was not fitted to (closure_dem_comparison.hpp runs the closure and measures;
// this file owns the split, the objective, the search and the sensitivity ranges).
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "continuum/closure/bed_friction.hpp"

namespace grainscale::studies {

inline constexpr double kAngleTolerance = 1.0;   // deg
inline constexpr double kSpeedTolerance = 0.5;   // of the DEM's RMS surface speed
inline constexpr double kSpeedFloor = 0.01;      // m/s: below this the DEM bed counts as still

/// Calibration of the closure's bed friction on the DEM's early frames, judged on the later ones (a
/// blocked hold-out in time, as issue 9 asks of every fit: never single frames). The frames with
/// t <= train_until train, the later ones test. Parameters (BedFriction, bed_friction.hpp):
///   internal_friction_deg  φ in [5, 45]       basal_friction_deg  δ in [1, 45]
///   flowing_layer_diameters  ℓ/d in [0.3, 300] (log scale)        delta_mu  Δμ in [0, 10]
///   start_excess_deg  Δθ = θ_start − θ_stop in [0, 15] (start/stop hysteresis, bed_friction.hpp (F3))
/// Objective on the training frames, the bar's own scales (both terms <= 1 is "agrees"):
///   J = (angle RMS / kAngleTolerance)² + (speed RMS / (kSpeedTolerance max(DEM RMS speed, kSpeedFloor)))²
/// minimised by a grid over the parameters' usual ranges, then Nelder–Mead (GSL nmsimplex2) from the
/// best grid point. The DEM's surface-speed measure keeps the a-priori flowing-layer depth, so the
/// data do not move with the fitted ℓ.
struct ClosureFitSettings {
  double train_until = NAN;             // [s]
  std::vector<std::string> parameters;  // names above; empty: φ, δ and ℓ/d
};

/// Bar errors on a block of frames.
struct BlockErrors {
  int frames = 0;
  double angle_rms_deg = NAN, speed_rms = NAN, dem_speed_rms = NAN;
  double objective = NAN;  // J above on this block
  bool agrees = false;     // the bar on this block
};

struct ClosureFit {
  ClosureFitSettings settings;
  std::vector<std::string> names;           // fitted parameters
  std::vector<double> a_priori, fitted;     // their values before and after
  std::vector<double> lower, upper;         // sensitivity: J_train <= J_min + 0.25 (others at the fit)
  BlockErrors a_priori_train, a_priori_test, fitted_train, fitted_test;
  int evaluations = 0;                      // closure runs
  std::vector<double> angle_deg, speed;     // the fitted closure (side walls) at every frame
};

/// Runs the closure with a friction and gives its free-surface angle [deg] and surface speed [m/s]
/// at every compared frame.
using ClosureRun = std::function<void(const continuum::closure::BedFriction&, std::vector<double>& angle_deg,
                                      std::vector<double>& speed)>;

/// The bar's errors of a closure series against the DEM's on frames [begin, end).
BlockErrors block_errors(const std::vector<double>& dem_angle_deg, const std::vector<double>& dem_speed,
                         const std::vector<double>& angle_deg, const std::vector<double>& speed, std::size_t begin,
                         std::size_t end);

/// Fits `settings.parameters` of `a_priori` (its side walls kept) to the frames at `times` up to
/// settings.train_until and evaluates both on the rest. `where` names the data in errors: an unknown
/// parameter, or fewer than 3 frames on either side of the split (InputError).
ClosureFit fit_closure_friction(const ClosureFitSettings& settings, const std::string& where,
                                const std::vector<double>& times, const std::vector<double>& dem_angle_deg,
                                const std::vector<double>& dem_speed, const continuum::closure::BedFriction& a_priori,
                                const ClosureRun& run);

}  // namespace grainscale::studies
