#include "continuum/terms/wall_mobility.hpp"

#include <algorithm>
#include <cmath>

namespace grainscale::continuum {

WallMobility::WallMobility(Limiter limiter)
    : FluxTerm("wall_mobility", {{"W", "m/s", 0.0, 0.0, 1.0, 1e-7, 1e-3, "upward drift of chaff at the end walls (WM1)"},
                                 {"length", "m", 0.02, 1e-6, 10.0, 4e-3, 5e-2, "decay length away from the walls", true}}),
      limiter_(limiter) {}

DriftField WallMobility::field(const TermContext& ctx) const {
  const Grid& g = ctx.grid;
  const double W = parameters().get("W"), ell = parameters().get("length");
  return {{}, [&g, W, ell](int i, int m) {
            const double x = g.x_centre(i), d = std::min(x, g.length() - x);
            return s_face_drift(g, i, m, 0.0, W * std::exp(-d / ell));
          }};
}

void WallMobility::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  if (parameters().get("W") == 0) return;
  add_drift_fluxes(ctx, c, faces_q(ctx), Mobility::symmetric, limiter_, states_, out);
}

void WallMobility::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  add_drift_rate_bound(ctx, faces_q(ctx), rate);
}

int WallMobility::jacobian_half_bandwidth(const Grid& g) const {
  return drift_half_bandwidth(g, {{}, [](int, int) { return 1.0; }}, limiter_);
}

const DriftCache& WallMobility::faces_q(const TermContext& ctx) const {
  std::vector<double> values;
  for (const auto& p : parameters().all()) values.push_back(p.value);
  return cache_.update(ctx, field(ctx), values);
}

}  // namespace grainscale::continuum
