#include "continuum/terms/surface_drift.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace grainscale::continuum {

SurfaceDrift::SurfaceDrift(Limiter limiter)
    : FluxTerm("surface_drift", {{"U", "m/s", 0.0, 0.0, 1.0, 1e-6, 1e-3, "drift speed of surface chaff towards the ends (SD1)"},
                                 {"thickness", "m", 0.01, 1e-6, 1.0, 4e-3, 3e-2, "thickness of the flowing surface layer", true}}),
      limiter_(limiter) {}

DriftField SurfaceDrift::field(const TermContext& ctx) const {
  const Grid& g = ctx.grid;
  const double U = parameters().get("U"), delta = parameters().get("thickness");
  return {[&g, U, delta](int f, int k) {
            const double h = g.h_node(f), dz = g.dsigma() * h;
            const double inside = std::clamp((k + 1) * dz - std::max(k * dz, h - delta), 0.0, dz);  // overlap with the layer
            const double vx = U * std::sin(std::numbers::pi * (g.x_face(f) / g.length() - 0.5));
            return vx * inside;
          },
          {}};
}

void SurfaceDrift::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  if (parameters().get("U") == 0) return;
  add_drift_fluxes(ctx, c, faces_q(ctx), Mobility::symmetric, limiter_, states_, out);
}

void SurfaceDrift::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  add_drift_rate_bound(ctx, faces_q(ctx), rate);
}

int SurfaceDrift::jacobian_half_bandwidth(const Grid& g) const {
  return drift_half_bandwidth(g, {[](int, int) { return 1.0; }, {}}, limiter_);
}

const DriftCache& SurfaceDrift::faces_q(const TermContext& ctx) const {
  std::vector<double> values;
  for (const auto& p : parameters().all()) values.push_back(p.value);
  return cache_.update(ctx, field(ctx), values);
}

}  // namespace grainscale::continuum
