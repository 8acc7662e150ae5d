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

void add_drift_fluxes(const TermContext& ctx, std::span<const double> c, const DriftField& drift, Mobility m,
                      Limiter limiter, FaceStates& states, FaceFluxes& out) {
  const Grid& g = ctx.grid;
  reconstruct(g, c, limiter, states);
  if (drift.x_face_q) {
    for (int f = 1; f < g.nx(); ++f) {
      for (int k = 0; k < g.nz(); ++k) {
        const std::size_t face = x_face(g, f, k);
        const double q = drift.x_face_q(f, k);
        if (q != 0) out.x[face] += drift_face_flux(m, q, states.x_left[face], states.x_right[face]);
      }
    }
  }
  if (drift.s_face_q) {
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 1; k < g.nz(); ++k) {
        const std::size_t face = s_face(g, i, k);
        const double q = drift.s_face_q(i, k);
        if (q != 0) out.s[face] += drift_face_flux(m, q, states.s_below[face], states.s_above[face]);
      }
    }
  }
}

void add_drift_rate_bound(const TermContext& ctx, const DriftField& drift, std::span<double> rate) {
  const Grid& g = ctx.grid;
  if (drift.x_face_q) {
    for (int f = 1; f < g.nx(); ++f) {
      for (int k = 0; k < g.nz(); ++k) {
        const double q = std::abs(drift.x_face_q(f, k));
        rate[g.index(f - 1, k)] += q / g.area(f - 1, k);
        rate[g.index(f, k)] += q / g.area(f, k);
      }
    }
  }
  if (drift.s_face_q) {
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 1; k < g.nz(); ++k) {
        const double q = std::abs(drift.s_face_q(i, k));
        rate[g.index(i, k - 1)] += q / g.area(i, k - 1);
        rate[g.index(i, k)] += q / g.area(i, k);
      }
    }
  }
}

int drift_half_bandwidth(const Grid& g, const DriftField& drift, Limiter limiter) {
  const int reach = limiter == Limiter::first_order ? 1 : 2;
  return drift.x_face_q ? reach * g.nz() : reach;
}

}  // namespace grainscale::continuum
