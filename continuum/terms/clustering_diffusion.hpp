#pragma once
// Concentration-dependent (clustering) diffusivity. Chaff flakes interlock into mats and clusters,
// so where chaff is concentrated it is moved about in pieces larger than a grain, and the mixing it
// sees grows with its own concentration (for the shear-induced diffusivity's dependence on the mixture
// see Fan et al. 2015, Phys. Rev. E 92, and the concentration-dependent diffusivity of
// Utter & Behringer 2004 in dense shear). Added to shear_diffusion.hpp:
//   D_c(c) = C_c γ̇ d² c,     flux −D_c(c) ∇c                                        (CD1)
// with c at the face the mean of its two cells (standard for a nonlinear diffusivity); the
// discretisation of −γ̇ d² ∇c with its cross terms is diffusion_stencil.hpp's. C_c [–] is fitted;
// d [m] is set (the grain diameter, as for shear_diffusion).
#include "continuum/flux_term.hpp"

namespace grainscale::continuum {

class ClusteringDiffusion final : public FluxTerm {
 public:
  ClusteringDiffusion();
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;

 private:
  mutable FaceFluxes scratch_;
};

}  // namespace grainscale::continuum
