#pragma once
// Friction of the grain on the container's side walls, for the 2-D (x, z) flow closure of a channel of
// width W (docs/hold_prediction.md, "Side walls").
//
// A section of a container has two vertical side walls a distance W apart, parallel to the flow. A
// layer of thickness a sliding between them presses on each wall with the hydrostatic pressure
// P = ρ g_n (a − ζ) (ζ the depth below the surface, earth-pressure coefficient 1) and is resisted there
// by Coulomb friction μ_w P. Integrated over the layer the two walls take 2 · μ_w ρ g_n a²/2; per unit
// width of the channel and divided by the layer's normal weight ρ g_n a this is an extra friction
// coefficient added to the basal one:
//
//   μ_eff = μ(h, I) + μ_w a / W                                                             (W1)
//
// so that steady flow down a plane inclined at θ has tan θ = μ(I) + μ_w a / W (Taberlet et al., Phys.
// Rev. Lett. 91:264301, 2003, "superstable" heaps in thin channels; Jop, Forterre & Pouliquen, J. Fluid
// Mech. 541:167, 2005, "Crucial role of sidewalls in granular surface flows", where h is the
// flowing-layer thickness). In this closure a is the flowing-layer thickness a(h) = ℓ(1 − e^{−h/ℓ})
// of bed_friction.hpp (= h for a plug, ℓ = ∞), so a plug of depth h in a channel of width W is held on
// a floor tilted by θ exactly while tan θ ≤ tan δ + μ_w h/W, and a planar surface of a bed with a
// surface layer while tan(θ − β) ≤ tan φ + μ_w a(h)/W.
// The term enters both the yield threshold and the moving friction (it is a Coulomb term, independent
// of speed). W = ∞ (no width stated) is a 2-D section without side walls: no term, the closure as
// before, bit for bit.
// Assumptions (not the papers'): the wall's normal stress equals the hydrostatic pressure (Janssen's
// coefficient K = 1, as Jop et al. assume); the walls resist the flowing layer only (the static grain
// below it does not move); the velocity across the channel is uniform (the 2-D closure's u is its mean).
#include <cmath>
#include <limits>

namespace grainscale::continuum::closure {

struct SideWallFriction {
  double width = std::numeric_limits<double>::infinity();  // W: distance between the side walls [m]
  double friction = 0;                                      // μ_w: grain-wall sliding friction coefficient

  /// Whether the section has side walls (a finite width).
  bool active() const { return std::isfinite(width); }
  /// The extra friction coefficient μ_w a / W of (W1) for a flowing layer of thickness a ≥ 0 [m].
  double mu(double a) const { return active() ? friction * a / width : 0.0; }
};

}  // namespace grainscale::continuum::closure
