#include "continuum/terms/pause_creep.hpp"

namespace grainscale::continuum {

PauseCreep::PauseCreep(Limiter limiter)
    : FluxTerm("pause_creep", {{"V", "m/s", 0.0, 0.0, 1.0, 1e-7, 1e-4, "rise speed of chaff in the creeping bed while paused (PC1)"},
                               {"pause_fraction", "-", 0.444, 0.0, 1.0, 0.0, 1.0, "fraction of the cycle spent paused (from the motion)", true}}),
      limiter_(limiter) {}

DriftField PauseCreep::field(const TermContext& ctx) const {
  const Grid& g = ctx.grid;
  const double v = parameters().get("V") * parameters().get("pause_fraction");
  return {{}, [&g, v](int i, int m) { return s_face_drift(g, i, m, 0.0, v); }};
}

void PauseCreep::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  if (parameters().get("V") * parameters().get("pause_fraction") == 0) return;
  add_drift_fluxes(ctx, c, faces_q(ctx), Mobility::symmetric, limiter_, states_, out);
}

void PauseCreep::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  add_drift_rate_bound(ctx, faces_q(ctx), rate);
}

int PauseCreep::jacobian_half_bandwidth(const Grid& g) const {
  return drift_half_bandwidth(g, {{}, [](int, int) { return 1.0; }}, limiter_);
}

const DriftCache& PauseCreep::faces_q(const TermContext& ctx) const {
  std::vector<double> values;
  for (const auto& p : parameters().all()) values.push_back(p.value);
  return cache_.update(ctx, field(ctx), values);
}

}  // namespace grainscale::continuum
