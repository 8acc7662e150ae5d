#include "continuum/diffusion_stencil.hpp"

#include <cmath>

namespace grainscale::continuum {

namespace {

/// ∂c/∂σ in column i at layer k: central inside, one-sided at the floor and surface cells.
double d_sigma(const Grid& g, std::span<const double> c, int i, int k) {
  const int nz = g.nz();
  if (nz == 1) return 0;
  if (k == 0) return (c[g.index(i, 1)] - c[g.index(i, 0)]) / g.dsigma();
  if (k == nz - 1) return (c[g.index(i, k)] - c[g.index(i, k - 1)]) / g.dsigma();
  return (c[g.index(i, k + 1)] - c[g.index(i, k - 1)]) / (2 * g.dsigma());
}

/// ∂c/∂ξ along layer k at column i: central inside, one-sided next to the walls.
double d_xi(const Grid& g, std::span<const double> c, int i, int k) {
  const int nx = g.nx();
  if (nx == 1) return 0;
  if (i == 0) return (c[g.index(1, k)] - c[g.index(0, k)]) / g.dx();
  if (i == nx - 1) return (c[g.index(i, k)] - c[g.index(i - 1, k)]) / g.dx();
  return (c[g.index(i + 1, k)] - c[g.index(i - 1, k)]) / (2 * g.dx());
}

}  // namespace

void add_diffusive_fluxes(const TermContext& ctx, std::span<const double> c, double per_shear, double constant,
                          FaceFluxes& out) {
  const Grid& g = ctx.grid;
  const int nx = g.nx(), nz = g.nz();
  const double ds = g.dsigma(), dx = g.dx();
  // Interior x-faces, eq. (D1).
  for (int f = 1; f < nx; ++f) {
    const double h = g.h_node(f), hx = g.slope_node(f);
    for (int k = 0; k < nz; ++k) {
      const std::size_t face = x_face(g, f, k);
      const double D = per_shear * ctx.faces.shear_x[face] + constant;
      const double c_xi = (c[g.index(f, k)] - c[g.index(f - 1, k)]) / dx;
      double cross = 0;
      if (hx != 0) {
        const double c_sigma = 0.5 * (d_sigma(g, c, f - 1, k) + d_sigma(g, c, f, k));
        cross = g.sigma_centre(k) * hx / h * c_sigma;
      }
      out.x[face] -= D * h * ds * (c_xi - cross);
    }
  }
  // Interior σ-faces, eq. (D2).
  for (int i = 0; i < nx; ++i) {
    const double h = g.h_column(i), hx = g.slope_column(i);
    for (int m = 1; m < nz; ++m) {
      const std::size_t face = s_face(g, i, m);
      const double D = per_shear * ctx.faces.shear_s[face] + constant;
      const double sigma = g.sigma_face(m);
      const double c_sigma = (c[g.index(i, m)] - c[g.index(i, m - 1)]) / ds;
      double flux_gradient = c_sigma / h;
      if (hx != 0) {
        const double c_xi = 0.5 * (d_xi(g, c, i, m - 1) + d_xi(g, c, i, m));
        flux_gradient = (1 + sigma * sigma * hx * hx) * c_sigma / h - sigma * hx * c_xi;
      }
      out.s[face] -= D * dx * flux_gradient;
    }
  }
}

void add_diffusive_rate_bound(const TermContext& ctx, double per_shear, double constant, std::span<double> rate) {
  const Grid& g = ctx.grid;
  const int nx = g.nx(), nz = g.nz();
  const double ds = g.dsigma(), dx = g.dx();
  for (int f = 1; f < nx; ++f) {
    const double h = g.h_node(f), hx = g.slope_node(f);
    for (int k = 0; k < nz; ++k) {
      const double D = per_shear * ctx.faces.shear_x[x_face(g, f, k)] + constant;
      // Normal part D h dσ / dx plus the cross part's weights (|σ h_x| dσ D / dσ spread over 4 cells).
      const double w = D * h * ds / dx + D * std::abs(g.sigma_centre(k) * hx);
      rate[g.index(f - 1, k)] += w / g.area(f - 1, k);
      rate[g.index(f, k)] += w / g.area(f, k);
    }
  }
  for (int i = 0; i < nx; ++i) {
    const double h = g.h_column(i), hx = g.slope_column(i);
    for (int m = 1; m < nz; ++m) {
      const double sigma = g.sigma_face(m);
      const double D = per_shear * ctx.faces.shear_s[s_face(g, i, m)] + constant;
      const double w = D * dx * (1 + sigma * sigma * hx * hx) / (h * ds) + D * std::abs(sigma * hx);
      rate[g.index(i, m - 1)] += w / g.area(i, m - 1);
      rate[g.index(i, m)] += w / g.area(i, m);
    }
  }
}

}  // namespace grainscale::continuum
