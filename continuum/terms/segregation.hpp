#pragma once
// Segregation of chaff relative to the grain, ∂/∂z [w_s c (1 − c)] with w_s = S γ̇ (Fan et al. 2014;
// the c(1−c) form from mixture theory, Gray & Thornton 2005). S > 0: chaff rises.
// The flux f(c) = w_s c (1 − c) is not monotone in c, so the face flux is Engquist–Osher's
//   F(c⁻, c⁺) = f(min(c⁻, ½)) + f(max(c⁺, ½)) − f(½)    for w_s ≥ 0 (mirrored for w_s < 0),
// with c⁻, c⁺ the MUSCL states below and above the face. It is monotone (non-decreasing in c⁻,
// non-increasing in c⁺), consistent, and zero when both states are 0 or both are 1, which is why
// c stays in [0, 1]. Only σ-faces carry it: the flux is vertical, and a vertical x-face has no
// vertical normal component.
#include "continuum/flux_term.hpp"
#include "continuum/reconstruction.hpp"

namespace grainscale::continuum {

class Segregation final : public FluxTerm {
 public:
  Segregation(double S, Limiter limiter);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;

 private:
  Limiter limiter_;
  mutable FaceStates states_;
};

/// Engquist–Osher flux for w c (1 − c) (exposed for tests).
double segregation_face_flux(double w, double c_below, double c_above);

}  // namespace grainscale::continuum
