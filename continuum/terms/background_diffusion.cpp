#include "continuum/terms/background_diffusion.hpp"

#include "continuum/diffusion_stencil.hpp"

namespace grainscale::continuum {

BackgroundDiffusion::BackgroundDiffusion(double D0)
    : FluxTerm("background_diffusion", {{"D0", "m^2/s", 0.0, 0.0, 10.0, 0.0, 1e-6, "shear-independent diffusivity"}}) {
  parameters().set("D0", D0);
}

void BackgroundDiffusion::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  add_diffusive_fluxes(ctx, c, 0.0, parameters().get("D0"), out);
}

void BackgroundDiffusion::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  add_diffusive_rate_bound(ctx, 0.0, parameters().get("D0"), rate);
}

int BackgroundDiffusion::jacobian_half_bandwidth(const Grid& g) const { return diffusion_half_bandwidth(g); }

}  // namespace grainscale::continuum
