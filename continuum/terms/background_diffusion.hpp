#pragma once
// Background diffusion, ∇·(D₀ ∇c): mixing not tied to the local shear rate (vibration, creep,
// and the floor of what the coarse-grained γ̇ resolves). Discretised by diffusion_stencil.hpp.
#include "continuum/flux_term.hpp"

namespace grainscale::continuum {

class BackgroundDiffusion final : public FluxTerm {
 public:
  explicit BackgroundDiffusion(double D0);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;
  bool implicit_in_imex() const override { return true; }
};

}  // namespace grainscale::continuum
