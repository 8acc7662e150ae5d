#include "continuum/terms/segregation.hpp"

#include <algorithm>
#include <cmath>

namespace grainscale::continuum {

double segregation_face_flux(double w, double c_below, double c_above) {
  auto f = [w](double c) { return w * c * (1 - c); };
  // f' = w (1 − 2c): for w ≥ 0 information travels up where c < ½ and down where c > ½.
  if (w >= 0) return f(std::min(c_below, 0.5)) + f(std::max(c_above, 0.5)) - f(0.5);
  return f(std::max(c_below, 0.5)) + f(std::min(c_above, 0.5)) - f(0.5);
}

Segregation::Segregation(double S, Limiter limiter)
    : FluxTerm("segregation", {{"S", "m", 0.0, -1.0, 1.0, 1e-5, 2e-2,
                                "segregation length: w_s = S γ̇ (positive: chaff rises)"}}),
      limiter_(limiter) {
  parameters().set("S", S);
}

void Segregation::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  const Grid& g = ctx.grid;
  const double S = parameters().get("S");
  if (S == 0) return;
  reconstruct(g, c, limiter_, states_);
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const std::size_t face = s_face(g, i, m);
      const double w = S * ctx.faces.shear_s[face];
      out.s[face] += g.dx() * segregation_face_flux(w, states_.s_below[face], states_.s_above[face]);
    }
  }
}

void Segregation::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  // |f'(c)| ≤ |w| for c in [0, 1].
  const Grid& g = ctx.grid;
  const double S = std::abs(parameters().get("S"));
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const double q = S * ctx.faces.shear_s[s_face(g, i, m)] * g.dx();
      rate[g.index(i, m - 1)] += q / g.area(i, m - 1);
      rate[g.index(i, m)] += q / g.area(i, m);
    }
  }
}

int Segregation::jacobian_half_bandwidth(const Grid& g) const {
  (void)g;
  return limiter_ == Limiter::first_order ? 1 : 2;  // within one column: layers k ± 2
}

}  // namespace grainscale::continuum
