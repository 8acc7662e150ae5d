#include "continuum/drift_flux.hpp"

#include <algorithm>
#include <cmath>

namespace grainscale::continuum {

double mobility(Mobility m, double c) { return m == Mobility::symmetric ? c * (1 - c) : c * (1 - c) * (1 - c); }

double drift_face_flux(Mobility m, double q, double c_minus, double c_plus) {
  const double peak = m == Mobility::symmetric ? 0.5 : 1.0 / 3.0;
  auto f = [&](double c) { return q * mobility(m, c); };
  if (q >= 0) return f(std::min(c_minus, peak)) + f(std::max(c_plus, peak)) - f(peak);
  return f(std::max(c_minus, peak)) + f(std::min(c_plus, peak)) - f(peak);
}

double s_face_drift(const Grid& g, int i, int m, double vx, double vz) {
  return (vz - g.sigma_face(m) * g.slope_column(i) * vx) * g.dx();
}

double x_face_drift(const Grid& g, int f, double vx) { return vx * g.h_node(f) * g.dsigma(); }

const DriftCache& DriftCache::update(const TermContext& ctx, const DriftField& drift, const std::vector<double>& parameters) {
  const Grid& g = ctx.grid;
  std::vector<double> key = parameters;
  key.insert(key.end(), {static_cast<double>(g.nx()), static_cast<double>(g.nz()), g.length(), g.total_area()});
  double shear = 0;
  for (double v : ctx.faces.shear_x) shear += v;
  for (double v : ctx.faces.shear_s) shear += v;
  key.push_back(shear);
  if (key == key_) return *this;
  key_ = key;
  x.assign(x_face_count(g), 0.0);
  s.assign(s_face_count(g), 0.0);
  if (drift.x_face_q) {
    for (int f = 1; f < g.nx(); ++f)
      for (int k = 0; k < g.nz(); ++k) x[x_face(g, f, k)] = drift.x_face_q(f, k);
  }
  if (drift.s_face_q) {
    for (int i = 0; i < g.nx(); ++i)
      for (int m = 1; m < g.nz(); ++m) s[s_face(g, i, m)] = drift.s_face_q(i, m);
  }
  return *this;
}

void add_drift_fluxes(const TermContext& ctx, std::span<const double> c, const DriftCache& q, Mobility m,
                      Limiter limiter, FaceStates& states, FaceFluxes& out) {
  const Grid& g = ctx.grid;
  reconstruct(g, c, limiter, states);
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const std::size_t face = x_face(g, f, k);
      if (q.x[face] != 0) out.x[face] += drift_face_flux(m, q.x[face], states.x_left[face], states.x_right[face]);
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 1; k < g.nz(); ++k) {
      const std::size_t face = s_face(g, i, k);
      if (q.s[face] != 0) out.s[face] += drift_face_flux(m, q.s[face], states.s_below[face], states.s_above[face]);
    }
  }
}

void add_drift_rate_bound(const TermContext& ctx, const DriftCache& q, std::span<double> rate) {
  const Grid& g = ctx.grid;
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const double v = std::abs(q.x[x_face(g, f, k)]);
      rate[g.index(f - 1, k)] += v / g.area(f - 1, k);
      rate[g.index(f, k)] += v / g.area(f, k);
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 1; k < g.nz(); ++k) {
      const double v = std::abs(q.s[s_face(g, i, k)]);
      rate[g.index(i, k - 1)] += v / g.area(i, k - 1);
      rate[g.index(i, k)] += v / g.area(i, k);
    }
  }
}

int drift_half_bandwidth(const Grid& g, const DriftField& drift, Limiter limiter) {
  const int reach = limiter == Limiter::first_order ? 1 : 2;
  return drift.x_face_q ? reach * g.nz() : reach;
}

}  // namespace grainscale::continuum
