#include "continuum/terms/lever_arm.hpp"

namespace grainscale::continuum {

namespace {
constexpr double kGravity = 9.81;
}

LeverArm::LeverArm(Limiter limiter)
    : FluxTerm("lever_arm", {{"S", "m", 0.0, 0.0, 1.0, 1e-4, 2e-2, "segregation length along the centrifugal part of g_eff (L1)"},
                             {"omega2", "1/s^2", 0.02, 0.0, 100.0, 0.0, 0.1, "cycle mean of ω² (from the motion)", true},
                             {"axis_x", "m", -0.6, -1e4, 1e4, -1e4, 1e4, "rotation axis x in the container frame", true},
                             {"axis_z", "m", -0.3, -1e4, 1e4, -1e4, 1e4, "rotation axis z in the container frame", true}}),
      limiter_(limiter) {}

std::pair<double, double> LeverArm::drift(double x, double z, double shear_rate) const {
  const double k = -parameters().get("S") * shear_rate * parameters().get("omega2") / kGravity;
  return {k * (x - parameters().get("axis_x")), k * (z - parameters().get("axis_z"))};
}

DriftField LeverArm::field(const TermContext& ctx) const {
  const Grid& g = ctx.grid;
  const FaceCoefficients& faces = ctx.faces;
  return {[this, &g, &faces](int f, int k) {
            const double z = (k + 0.5) * g.dsigma() * g.h_node(f);
            return x_face_drift(g, f, drift(g.x_face(f), z, faces.shear_x[x_face(g, f, k)]).first);
          },
          [this, &g, &faces](int i, int m) {
            const auto [vx, vz] = drift(g.x_centre(i), g.sigma_face(m) * g.h_column(i), faces.shear_s[s_face(g, i, m)]);
            return s_face_drift(g, i, m, vx, vz);
          }};
}

void LeverArm::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  if (parameters().get("S") == 0 || parameters().get("omega2") == 0) return;
  add_drift_fluxes(ctx, c, faces_q(ctx), Mobility::symmetric, limiter_, states_, out);
}

void LeverArm::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  add_drift_rate_bound(ctx, faces_q(ctx), rate);
}

int LeverArm::jacobian_half_bandwidth(const Grid& g) const { return drift_half_bandwidth(g, {[](int, int) { return 1.0; }, {}}, limiter_); }

const DriftCache& LeverArm::faces_q(const TermContext& ctx) const {
  std::vector<double> values;
  for (const auto& p : parameters().all()) values.push_back(p.value);
  return cache_.update(ctx, field(ctx), values);
}

}  // namespace grainscale::continuum
