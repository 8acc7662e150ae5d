#pragma once
// Lever-arm accelerations of a container off its rotation axis. In the container frame the grain
// feels g_eff = g − α × r − ω × (ω × r) (r from the axis; Euler and centrifugal terms). Over a
// symmetric tilting cycle the tilt's own component of g and the Euler term α × r average to zero;
// the centrifugal part ω² r⊥ does not: its cycle mean ⟨ω²⟩ (x − x_a, z − z_a) points away from the
// axis. Light chaff segregates against g_eff (segregation.hpp: against g, w_s = S γ̇), so its
// cycle-mean drift relative to the grain is
//   v = −S_l γ̇ ⟨ω²⟩ (x − x_a, z − z_a) / g                                          (L1)
// carried as q c (1 − c) (drift_flux.hpp). S_l [m] is the segregation length for this horizontal
// forcing (fitted; the same order as segregation.S if the mechanism is the same); ⟨ω²⟩ and the axis
// position (x_a, z_a) in the container frame come from the experiment's motion and geometry
// (`grainscale loop` reads them from the DEM scenario). For the report's box (24°, 0.1 Hz, 4 s
// pauses) ⟨ω²⟩ ≈ 0.019 1/s², so |a|/g ≈ 0.002 per metre of arm: small in a platform box, of order
// 0.02–0.05 in a ship's hold 10–20 m from the roll axis.
#include "continuum/drift_flux.hpp"

namespace grainscale::continuum {

class LeverArm final : public FluxTerm {
 public:
  explicit LeverArm(Limiter limiter);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;
  /// (L1) at (x, z) for shear rate γ̇: the drift velocity (vx, vz) [m/s].
  std::pair<double, double> drift(double x, double z, double shear_rate) const;

 private:
  DriftField field(const TermContext& ctx) const;
  const DriftCache& faces_q(const TermContext& ctx) const;
  Limiter limiter_;
  mutable FaceStates states_;
  mutable DriftCache cache_;
};

}  // namespace grainscale::continuum
