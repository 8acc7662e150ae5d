#pragma once
// Creep and segregation during the motion's pauses. The platform holds at each end of its tilt
// (4 s of every 18 s cycle in the report); the phase-averaged γ̇ the model is given is small then,
// so segregation ∝ γ̇ (segregation.hpp) stops, but a tilted bed keeps creeping (slow, intermittent
// rearrangements; Komatsu et al., Phys. Rev. Lett. 86 (2001) 1757: creep decays exponentially with
// depth below a surface flow), and light chaff keeps rising through it. The cycle-mean effect is a
// rise that does not scale with γ̇, weighted by the time spent paused:
//   v_z = f_p V                                                                      (PC1)
// carried as q c (1 − c) (drift_flux.hpp) through σ-faces. V [m/s] (rise speed while paused) is
// fitted; the pause fraction f_p comes from the motion (`grainscale loop` reads the scenario).
#include "continuum/drift_flux.hpp"

namespace grainscale::continuum {

class PauseCreep final : public FluxTerm {
 public:
  explicit PauseCreep(Limiter limiter);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;

 private:
  DriftField field(const TermContext& ctx) const;
  const DriftCache& faces_q(const TermContext& ctx) const;
  Limiter limiter_;
  mutable FaceStates states_;
  mutable DriftCache cache_;
};

}  // namespace grainscale::continuum
