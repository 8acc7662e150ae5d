#include "continuum/terms/clustering_diffusion.hpp"

#include "continuum/diffusion_stencil.hpp"

namespace grainscale::continuum {

ClusteringDiffusion::ClusteringDiffusion()
    : FluxTerm("clustering_diffusion", {{"C", "-", 0.0, 0.0, 100.0, 0.01, 1.0, "D_c = C_c γ̇ d² c (CD1)"},
                                        {"d", "m", 4e-3, 1e-6, 1.0, 1e-3, 8e-3, "mean grain diameter", true}}) {}

void ClusteringDiffusion::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  const double d = parameters().get("d"), per_shear = parameters().get("C") * d * d;
  if (per_shear == 0) return;
  const Grid& g = ctx.grid;
  scratch_.reset(g);
  add_diffusive_fluxes(ctx, c, per_shear, 0.0, scratch_);
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const std::size_t face = x_face(g, f, k);
      out.x[face] += scratch_.x[face] * 0.5 * (c[g.index(f - 1, k)] + c[g.index(f, k)]);
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const std::size_t face = s_face(g, i, m);
      out.s[face] += scratch_.s[face] * 0.5 * (c[g.index(i, m - 1)] + c[g.index(i, m)]);
    }
  }
}

void ClusteringDiffusion::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  // |∂F/∂c| ≤ (c̄ + |Δc| / 2) × the linear coefficient ≤ 1.5 × it for c in [0, 1].
  const double d = parameters().get("d");
  add_diffusive_rate_bound(ctx, 1.5 * parameters().get("C") * d * d, 0.0, rate);
}

int ClusteringDiffusion::jacobian_half_bandwidth(const Grid& g) const { return diffusion_half_bandwidth(g); }

}  // namespace grainscale::continuum
