#include "continuum/terms/shear_diffusion.hpp"

#include "continuum/diffusion_stencil.hpp"

namespace grainscale::continuum {

ShearDiffusion::ShearDiffusion(double C, double d)
    : FluxTerm("shear_diffusion", {{"C", "-", 0.0, 0.0, 10.0, 0.01, 0.2, "D_γ = C γ̇ d²"},
                                   {"d", "m", 1e-3, 1e-6, 1.0, 1e-3, 8e-3, "mean grain diameter"}}) {
  parameters().set("C", C);
  parameters().set("d", d);
}

double ShearDiffusion::per_shear() const {
  const double d = parameters().get("d");
  return parameters().get("C") * d * d;
}

void ShearDiffusion::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  add_diffusive_fluxes(ctx, c, per_shear(), 0.0, out);
}

void ShearDiffusion::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  add_diffusive_rate_bound(ctx, per_shear(), 0.0, rate);
}

int ShearDiffusion::jacobian_half_bandwidth(const Grid& g) const { return diffusion_half_bandwidth(g); }

}  // namespace grainscale::continuum
