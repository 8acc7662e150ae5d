#pragma once
// Concentration-dependent segregation velocity. Segregation of a few intruders among many grains is
// faster than that of a mixture near 50/50 (Gajjar & Gray, J. Fluid Mech. 757 (2014) 297–329: an
// asymmetric flux; van der Vaart et al., Phys. Rev. Lett. 114 (2015) 238001; Jones et al.,
// J. Fluid Mech. 854 (2018) R1: w_s ∝ (1 − c) for the minority species). Added to the symmetric
// segregation.hpp term, a velocity S_c γ̇ (1 − c) gives the extra upward flux
//   F = S_c γ̇ c (1 − c)²                                                            (CS1)
// i.e. w_s(c) = S γ̇ + S_c γ̇ (1 − c): dilute chaff rises faster than chaff-rich mixture. S_c [m] is
// fitted. Vertical, through σ-faces only (as segregation.hpp), Engquist–Osher with c* = ⅓.
#include "continuum/drift_flux.hpp"

namespace grainscale::continuum {

class ConcentrationSegregation final : public FluxTerm {
 public:
  explicit ConcentrationSegregation(Limiter limiter);
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
