#pragma once
// Advection by the bulk flow, ∇·(u c): upwind flux q⁺ c_L + q⁻ c_R through each face, with q the
// face volume flux (face_coefficients.hpp) and c_L, c_R the MUSCL face states (reconstruction.hpp).
// Parameter: velocity_scale [-] multiplies u (1 = the flow as given; lets a fit absorb a
// phase-averaging bias in the coarse-grained velocity).
#include "continuum/flux_term.hpp"
#include "continuum/reconstruction.hpp"

namespace grainscale::continuum {

class Advection final : public FluxTerm {
 public:
  explicit Advection(Limiter limiter, double velocity_scale = 1.0);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;
  Limiter limiter() const { return limiter_; }

 private:
  Limiter limiter_;
  mutable FaceStates states_;  // scratch, reused between calls
};

}  // namespace grainscale::continuum
