#include "continuum/terms/concentration_segregation.hpp"

namespace grainscale::continuum {

ConcentrationSegregation::ConcentrationSegregation(Limiter limiter)
    : FluxTerm("concentration_segregation",
               {{"S", "m", 0.0, 0.0, 1.0, 1e-5, 2e-2, "extra segregation length of dilute chaff: w_s = (S + S_c (1 − c)) γ̇ (CS1)"}}),
      limiter_(limiter) {}

DriftField ConcentrationSegregation::field(const TermContext& ctx) const {
  const Grid& g = ctx.grid;
  const FaceCoefficients& faces = ctx.faces;
  const double S = parameters().get("S");
  return {{}, [&g, &faces, S](int i, int m) { return S * faces.shear_s[s_face(g, i, m)] * g.dx(); }};
}

void ConcentrationSegregation::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  if (parameters().get("S") == 0) return;
  add_drift_fluxes(ctx, c, faces_q(ctx), Mobility::dilute, limiter_, states_, out);
}

void ConcentrationSegregation::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  add_drift_rate_bound(ctx, faces_q(ctx), rate);
}

int ConcentrationSegregation::jacobian_half_bandwidth(const Grid& g) const {
  return drift_half_bandwidth(g, {{}, [](int, int) { return 1.0; }}, limiter_);
}

const DriftCache& ConcentrationSegregation::faces_q(const TermContext& ctx) const {
  std::vector<double> values;
  for (const auto& p : parameters().all()) values.push_back(p.value);
  return cache_.update(ctx, field(ctx), values);
}

}  // namespace grainscale::continuum
