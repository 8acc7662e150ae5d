#pragma once
// Diffusive flux −D ∇c through the faces of the terrain-following grid, with the cross terms that
// the sloping σ-faces bring in. In (ξ = x, σ = z / h(x)):
//   ∂c/∂x|_z = c_ξ − (σ h_x / h) c_σ,   ∂c/∂z = c_σ / h,
// so through an x-face (vertical, length h dσ)
//   F = −D h dσ [ c_ξ − (σ h_x / h) c_σ ]                                        (D1)
// and upward through a σ-face (normal·ds = (−σ h_x, 1) dx)
//   F = −D dx [ (1 + σ² h_x²) c_σ / h − σ h_x c_ξ ].                             (D2)
// The normal derivatives (c_ξ in D1, c_σ in D2) are two-point differences; the tangential ones are
// averages of the neighbouring cells' central differences. On a flat bed (h_x = 0) this is the
// five-point scheme. Second order for smooth h (tests/continuum/test_diffusion.cpp).
#include <span>

#include "continuum/flux_term.hpp"

namespace grainscale::continuum {

/// Add fluxes for D = per_shear · γ̇ + constant [m²/s], γ̇ taken on each face.
void add_diffusive_fluxes(const TermContext& ctx, std::span<const double> c, double per_shear, double constant,
                          FaceFluxes& out);

/// Add Σ_faces |coefficient| / area per cell for the same D (explicit stability bound).
void add_diffusive_rate_bound(const TermContext& ctx, double per_shear, double constant, std::span<double> rate);

/// Band half-width of the stencil: neighbours (i±1, k±1) are nz ± 1 apart.
inline int diffusion_half_bandwidth(const Grid& g) { return g.nz() + 1; }

}  // namespace grainscale::continuum
