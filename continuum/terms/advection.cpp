#include "continuum/terms/advection.hpp"

#include <algorithm>
#include <cmath>

namespace grainscale::continuum {

Advection::Advection(Limiter limiter, double velocity_scale)
    : FluxTerm("advection", {{"velocity_scale", "-", 1.0, 0.0, 100.0, 0.5, 1.5,
                              "multiplier on the coarse-grained bulk velocity", true}}),
      limiter_(limiter) {
  parameters().set("velocity_scale", velocity_scale);
}

void Advection::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  const Grid& g = ctx.grid;
  const double scale = parameters().get("velocity_scale");
  reconstruct(g, c, limiter_, states_);
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const std::size_t face = x_face(g, f, k);
      const double q = scale * ctx.faces.volume_flux_x[face];
      out.x[face] += std::max(q, 0.0) * states_.x_left[face] + std::min(q, 0.0) * states_.x_right[face];
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const std::size_t face = s_face(g, i, m);
      const double q = scale * ctx.faces.volume_flux_s[face];
      out.s[face] += std::max(q, 0.0) * states_.s_below[face] + std::min(q, 0.0) * states_.s_above[face];
    }
  }
}

void Advection::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  const Grid& g = ctx.grid;
  const double scale = parameters().get("velocity_scale");
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const double q = std::abs(scale * ctx.faces.volume_flux_x[x_face(g, f, k)]);
      rate[g.index(f - 1, k)] += q / g.area(f - 1, k);
      rate[g.index(f, k)] += q / g.area(f, k);
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const double q = std::abs(scale * ctx.faces.volume_flux_s[s_face(g, i, m)]);
      rate[g.index(i, m - 1)] += q / g.area(i, m - 1);
      rate[g.index(i, m)] += q / g.area(i, m);
    }
  }
}

int Advection::jacobian_half_bandwidth(const Grid& g) const {
  // A face state uses cells up to two columns away (MUSCL), i.e. 2 nz in index.
  return limiter_ == Limiter::first_order ? g.nz() : 2 * g.nz();
}

}  // namespace grainscale::continuum
