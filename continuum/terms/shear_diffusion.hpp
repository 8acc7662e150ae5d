#pragma once
// Shear-induced diffusion, ∇·(D_γ ∇c) with D_γ = C γ̇ d² (Bridgwater 1980; Utter & Behringer 2004;
// used by Fan et al. 2014). d is the mean grain diameter. Discretised by diffusion_stencil.hpp.
#include "continuum/flux_term.hpp"

namespace grainscale::continuum {

class ShearDiffusion final : public FluxTerm {
 public:
  ShearDiffusion(double C, double d);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;
  bool implicit_in_imex() const override { return true; }

 private:
  double per_shear() const;  // C d² [m²]
};

}  // namespace grainscale::continuum
