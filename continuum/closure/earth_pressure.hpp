#pragma once
// The earth-pressure coefficient of the depth-averaged flow closure (shallow_granular_flow.hpp): the
// ratio of the along-floor to the floor-normal stress that turns the bed's depth gradient into a force,
// −K g_n ∂h/∂x in (S2).
//
// Hydrostatic (the default): K = 1, as a fluid.
//
// Savage & Hutter (J. Fluid Mech. 199, 1989, eq. 3.5; moving frames: Gray, Wieland & Hutter, Proc. R.
// Soc. A 455, 1999, eq. 2.9): a Coulomb material with internal friction φ sliding on a floor with
// basal friction δ ≤ φ is at the Mohr–Coulomb limit, active where it extends (∂u/∂x > 0) and passive
// where it is compressed (∂u/∂x < 0):
//
//   K_act/pass = 2 sec²φ [1 ∓ √(1 − cos²φ sec²δ)] − 1                                      (K1)
//
// Limits that check it: δ = 0 gives Rankine's (1 ∓ sin φ)/(1 ± sin φ); δ = φ gives one value for both,
// (1 + sin²φ)/cos²φ. A bed piled against a wall on a floor tilted by θ > δ is therefore held with a
// surface slope h_x = (tan θ − tan δ)/K_pass relative to the floor (K_pass > 1: a steeper surface than
// the fluid-like K = 1 gives), and a bed spreading away from a wall is pushed harder (K_act < 1 holds it
// less). For δ > φ the floor is rougher than the grain; (K1) is taken at δ = φ, as (F2) takes min(δ, φ).
#include <algorithm>
#include <cmath>

namespace grainscale::continuum::closure {

struct EarthPressure {
  double active = 1, passive = 1;

  /// K = 1 for both.
  static EarthPressure hydrostatic() { return {}; }

  /// (K1) for internal friction φ and basal friction δ [rad], 0 ≤ δ, 0 < φ < π/2.
  static EarthPressure savage_hutter(double phi, double delta) {
    const double d = std::min(delta, phi);
    const double c2 = std::cos(phi) * std::cos(phi), sec2 = 1 / c2;
    const double root = std::sqrt(std::max(0.0, 1 - c2 / (std::cos(d) * std::cos(d))));
    return {2 * sec2 * (1 - root) - 1, 2 * sec2 * (1 + root) - 1};
  }

  /// K for a bed whose speed changes along the floor at the rate `dudx`: active when it extends,
  /// passive when it is compressed, 1 when it moves as a block or not at all.
  double at(double dudx) const { return dudx > 0 ? active : dudx < 0 ? passive : 1.0; }
};

}  // namespace grainscale::continuum::closure
