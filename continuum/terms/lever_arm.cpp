#include "continuum/terms/lever_arm.hpp"

#include <algorithm>

namespace grainscale::continuum {

LeverArm::LeverArm(Limiter limiter)
    : FluxTerm("lever_arm", {{"S", "m", 0.0, 0.0, 1.0, 1e-4, 2e-2, "segregation length along the cycle-mean anomaly of g_eff (L1)"},
                             {"omega2", "1/s^2", 0.02, 0.0, 100.0, 0.0, 0.1, "cycle mean of ω² (from the motion)", true},
                             {"alpha2", "1/s^4", 0.0, 0.0, 1e4, 0.0, 1.0, "cycle mean of α² (from the motion); 0: centrifugal part only", true},
                             {"axis_x", "m", -0.6, -1e4, 1e4, -1e4, 1e4, "rotation axis x in the container frame", true},
                             {"axis_z", "m", -0.3, -1e4, 1e4, -1e4, 1e4, "rotation axis z in the container frame", true},
                             {"mu", "-", 0.0, 0.0, 2.0, 0.0, 2.0, "static friction of the bed, tan of its repose angle (G2); 0: mean slope", true},
                             {"rate", "1/s", 0.0, 0.0, 1e3, 0.0, 1e3, "mobility rate of the whole bed; 0: the local shear rate", true},
                             {"layer", "m", 0.0, 0.0, 1.0, 4e-3, 3e-2, "the drift acts in this top layer only (L2); 0: the whole depth", true}}),
      limiter_(limiter) {}

CycleMotion LeverArm::motion() const {
  const ParameterSet& p = parameters();
  return {p.get("omega2"), p.get("alpha2"), p.get("axis_x"), p.get("axis_z"), p.get("mu")};
}

double LeverArm::mobility_rate(double shear_rate) const {
  const double rate = parameters().get("rate");
  return rate > 0 ? rate : shear_rate;
}

std::pair<double, double> LeverArm::drift(double x, double z, double shear_rate) const {
  const auto [ax, az] = effective_gravity_anomaly(motion(), x, z);
  const double k = -parameters().get("S") * mobility_rate(shear_rate);
  return {k * ax, k * az};
}

const AnomalyTable& LeverArm::table(const Grid& g) const {
  const auto& h = g.surface_nodes();
  const double top = *std::max_element(h.begin(), h.end());
  if (!(table_.motion() == motion()) || !table_.covers(0, g.length(), 0, top)) {
    table_ = AnomalyTable(motion(), 0, g.length(), 0, 2 * top);
  }
  return table_;
}

DriftField LeverArm::field(const TermContext& ctx) const {
  const Grid& g = ctx.grid;
  const FaceCoefficients& faces = ctx.faces;
  const AnomalyTable& a = table(g);
  const double S = parameters().get("S"), layer = parameters().get("layer");
  return {[this, &g, &faces, &a, S, layer](int f, int k) {
            const double h = g.h_node(f), dz = g.dsigma() * h;
            const double vx = -S * mobility_rate(faces.shear_x[x_face(g, f, k)]) * a.at(g.x_face(f), (k + 0.5) * dz).first;
            if (layer <= 0) return x_face_drift(g, f, vx);
            return vx * std::clamp((k + 1) * dz - std::max(k * dz, h - layer), 0.0, dz);  // (L2): the face's part in the layer
          },
          [this, &g, &faces, &a, S, layer](int i, int m) {
            const double h = g.h_column(i), z = g.sigma_face(m) * h;
            // (L2): a σ-face counts fully a half cell above the layer's bottom, not at all a half cell
            // below it, by a smooth step between (u² (3 − 2u), C¹): continuous in δ with a continuous
            // derivative, so a fit of δ neither stalls where the layer's bottom crosses a face nor
            // settles on a corner of the weights (a clamped linear ramp biased S_l by 4 % there).
            const double u = std::clamp((z - (h - layer)) / (g.dsigma() * h) + 0.5, 0.0, 1.0);
            const double in_layer = layer > 0 ? u * u * (3 - 2 * u) : 1.0;
            if (in_layer == 0) return 0.0;
            const auto [ax, az] = a.at(g.x_centre(i), z);
            const double k = -S * in_layer * mobility_rate(faces.shear_s[s_face(g, i, m)]);
            return s_face_drift(g, i, m, k * ax, k * az);
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
