#pragma once
// Friction of the grain bed for the depth-averaged flow closure (docs/hold_prediction.md, "Friction").
//
// Coulomb yield with a rate-dependent part, the depth-averaged μ(I) law of Pouliquen & Forterre
// (J. Fluid Mech. 453, 2002) in the form of Jop, Forterre & Pouliquen (J. Fluid Mech. 541, 2005):
//
//   μ(h, I) = μ_s(h) + Δμ · I / (I₀ + I),     I = |u| d / (a √(g_n a))                  (F1)
//
// with a the thickness of the flowing layer (shallow_granular_flow.hpp, a = ℓ(1 − e^{−h/ℓ})) and
// g_n the gravity normal to the floor. The static coefficient depends on where the bed fails:
//
//   μ_s(h) = tan φ + (min(tan δ, tan φ) − tan φ) e^{−h/ℓ}                                (F2)
//
// φ the internal friction angle of the grain (its angle of repose), δ the friction angle of grain on
// the floor, ℓ the flowing-layer depth. In a deep bed (h ≫ ℓ) the moving layer slides on static
// grain (tan φ); a layer thinner than ℓ slides on the floor (tan δ, if lower). The blend with the
// weight e^{−h/ℓ} (the fraction of the surface speed the exponential profile still has at the
// floor) is this closure's assumption, not a published law.
//
// Δμ = 0 gives a pure Coulomb material (flows, once yielded, are resisted by tan φ only).
//
// Start/stop hysteresis (Pouliquen, Phys. Fluids 11, 1999; Daerr & Douady, Nature 399, 1999): a bed
// at rest starts only above a steeper angle θ_start = φ + Δθ than the angle θ_stop = φ at which a
// moving layer stops. A face of the closure at rest yields at
//
//   μ_start(h) = μ_s(h) + [tan(φ + Δθ) − tan φ] (1 − e^{−h/ℓ})                             (F3)
//
// and, once moving, is resisted by (F1) (which starts from μ_s). The excess acts where the bed fails
// inside the grain (weight 1 − e^{−h/ℓ}), not on the floor: the DEM's contacts have one Coulomb
// coefficient, static and sliding alike, so sliding on the floor has no start/stop gap of its own.
// Δθ = 0 (the default) is the closure without hysteresis, bit for bit.
//
// Side walls (side_wall_friction.hpp, (W1)): a section of a channel of width W adds μ_w a(h)/W to μ_s,
// so to the threshold and, through (F1), to the moving friction. No width: no term.
#include <cmath>
#include <limits>

#include "continuum/closure/earth_pressure.hpp"
#include "continuum/closure/side_wall_friction.hpp"

#include "dem/yaml_map.hpp"

namespace grainscale::continuum::closure {

struct BedFriction {
  double internal_deg = 26.7;   // φ: barley's measured angle of repose (source_measurements.yaml)
  double basal_deg = 14.0;      // δ: grain on the floor; atan(0.25), barley-perspex sliding friction (Table 1)
  double delta_mu = 0;          // Δμ of (F1); Jop et al. 2005 (glass beads): tan 32.76° − tan 20.9° = 0.26
  double start_excess_deg = 0;  // Δθ of (F3): θ_start − θ_stop [deg]
  double i0 = 0.279;            // I₀ of (F1), Jop et al. 2005
  double grain_diameter = 4e-3; // d [m]
  /// ℓ [m]: e-folding depth of the velocity profile; +∞: plug flow over the whole depth (classical
  /// Savage–Hutter, a = h, μ_s = min(tan δ, tan φ)).
  double layer_depth = 0.04;
  SideWallFriction side_walls;  // none unless a width is given
  /// The earth pressure of (S2): hydrostatic (K = 1) unless Savage–Hutter's (K1) is asked for, from
  /// φ and δ above (earth_pressure.hpp).
  bool savage_hutter_pressure = false;

  EarthPressure earth_pressure() const;

  /// (F2) plus the side walls' μ_w a(h)/W (W1).
  double mu_static(double h) const;
  /// (F3): the yield threshold of a bed at rest (= mu_static(h) for Δθ = 0).
  double mu_start(double h) const;
  /// (F1) at speed |u| ≥ 0 in a layer of thickness a > 0 with normal gravity g_n > 0.
  double mu(double h, double a, double speed, double g_normal) const;
  /// e^{−h/ℓ} complement: 0 for a plug on the floor, → 1 for a surface layer on a deep bed.
  double surface_weight(double h) const;
  /// Flowing-layer thickness a(h) = ℓ (1 − e^{−h/ℓ}) (= h for ℓ = ∞).
  double active_depth(double h) const;
};

/// Reads `{internal_friction_deg, basal_friction_deg, delta_mu, start_excess_deg, i0, grain_diameter,
/// flowing_layer_diameters | flowing_layer_depth | plug: true, wall_friction, earth_pressure:
/// hydrostatic | savage_hutter}`; every key optional (defaults above, start_excess_deg in [0, 30],
/// flowing layer 10 grain diameters, wall_friction μ_w in [0, 2] defaults to tan δ: side walls of the
/// floor's material). The side walls' width is the container's, set by the caller (none here).
/// Throws InputError naming file, key and range.
BedFriction bed_friction_from_yaml(YamlMap m);

}  // namespace grainscale::continuum::closure
