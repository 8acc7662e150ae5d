#include "continuum/closure/shallow_granular_flow.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dem/input_error.hpp"

namespace grainscale::continuum::closure {

ShallowGranularFlow::ShallowGranularFlow(SectionSettings settings, ContainerGravity gravity,
                                         std::vector<double> depth, double t0)
    : s_(settings), gravity_(std::move(gravity)), t_(t0), h_(std::move(depth)) {
  if (!(s_.length > 0) || s_.nx < 2) throw InputError("flow closure: length must be > 0 and nx >= 2");
  if (static_cast<int>(h_.size()) != s_.nx) throw InputError("flow closure: need one depth per cell");
  for (double h : h_) {
    if (!(h >= 0) || !std::isfinite(h)) throw InputError("flow closure: depths must be finite and >= 0");
  }
  if (!(s_.cfl > 0 && s_.cfl <= 0.5)) throw InputError("flow closure: cfl must be in (0, 0.5]");
  dx_ = s_.length / s_.nx;
  u_.assign(s_.nx + 1, 0.0);
  q_.assign(s_.nx + 1, 0.0);
  a_.resize(s_.nx);
  pressure_ = s_.friction.earth_pressure();
}

double ShallowGranularFlow::volume() const {
  double v = 0;
  for (double h : h_) v += h;
  return v * dx_;
}

double ShallowGranularFlow::stable_dt() const {
  const auto st = gravity_.state(t_);
  double fastest = 0;
  for (int f = 1; f < s_.nx; ++f) {
    double gt = 0, gn = 0;
    gravity_.components(st, f * dx_, gt, gn);
    const double a = s_.friction.active_depth(std::max(h_[f - 1], h_[f]));
    fastest = std::max(fastest, std::abs(u_[f]) + std::sqrt(std::max(gn, 0.0) * a));
  }
  return fastest > 0 ? std::min(s_.cfl * dx_ / fastest, s_.max_dt) : s_.max_dt;
}

namespace {

/// v ≥ 0 with v + k μ(v) = w (μ non-decreasing in v), given that w > k μ(0).
double friction_solve(const BedFriction& fr, double h, double a, double gn, double k, double w) {
  if (fr.delta_mu <= 0) return w - k * fr.mu_static(h);
  double lo = 0, hi = w;  // residual(lo) < 0 ≤ residual(hi)
  for (int it = 0; it < 60 && hi - lo > 1e-14 * w; ++it) {
    const double mid = 0.5 * (lo + hi);
    (mid + k * fr.mu(h, a, mid, gn) < w ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

void ShallowGranularFlow::step(double dt) {
  const int n = s_.nx;
  const auto st = gravity_.state(t_);
  for (int i = 0; i < n; ++i) a_[i] = s_.friction.active_depth(h_[i]);
  std::vector<double>& u = u_;
  // Momentum (S2) at interior faces, from the old u (Jacobi: a copy of the neighbours is needed).
  std::vector<double> un(u);
  const bool sh = s_.friction.savage_hutter_pressure;
  for (int f = 1; f < n; ++f) {
    double gt = 0, gn = 0;
    gravity_.components(st, f * dx_, gt, gn);
    if (!(gn > 0)) {
      std::ostringstream m;
      m << "flow closure: gravity into the floor is not positive (g_n = " << gn << " m/s^2 at x = " << f * dx_
        << " m, t = " << t_ << " s): the motion lifts the grain off the floor, outside this model";
      throw std::runtime_error(m.str());
    }
    // Momentum-conservative upwind advection (Stelling & Duinmeijer 2003, eq. 15): the cell-centred
    // flux of the upstream cell carries momentum into the face, so a front moving onto a dry floor
    // has the speed of the flow behind it.
    const double qa = 0.5 * (q_[f - 1] + q_[f]), qb = 0.5 * (q_[f] + q_[f + 1]);
    const double abar = 0.5 * (a_[f - 1] + a_[f]);
    double adv = 0;
    if (abar > 0) {
      if (qa > 0) adv += qa / abar * (u[f] - u[f - 1]) / dx_;
      if (qb < 0) adv += qb / abar * (u[f + 1] - u[f]) / dx_;
    }
    const double slope = (h_[f] - h_[f - 1]) / dx_;
    // Earth pressure (earth_pressure.hpp): K = 1, or Savage–Hutter's. A moving face takes K from the
    // strain rate (central difference of the old speeds: active where the bed extends, passive where
    // it is compressed). A face at rest can take any K between the active and the passive limit (a
    // static bed's earth pressure is indeterminate there), so it takes the one nearest to holding it:
    // it stays at rest if any admissible K holds it, and starts at the limit that resists most.
    double K = 1.0;
    if (sh && slope != 0) {
      K = u[f] != 0 ? pressure_.at(u[f + 1] - u[f - 1])
                    : std::clamp((gt - adv) / (gn * slope), pressure_.active, pressure_.passive);
    }
    const double drive = gt - K * gn * slope - adv;
    const double hf = 0.5 * (h_[f - 1] + h_[f]);
    const double af = s_.friction.active_depth(hf);
    // Normal load (S3): on the floor for a plug, on the free surface for a surface layer.
    const double load = std::max(gn + s_.friction.surface_weight(hf) * gt * slope, 0.0);
    const double ustar = u[f] + dt * drive;
    const double k = dt * load;
    const double w = std::abs(ustar);
    // Start/stop hysteresis (bed_friction.hpp, (F3)): a face at rest yields at μ_start, a moving one
    // keeps moving while the drive exceeds μ_s.
    const double yield = u[f] == 0 ? s_.friction.mu_start(hf) : s_.friction.mu_static(hf);
    double v = 0;
    if (w > k * yield) v = friction_solve(s_.friction, hf, af, load, k, w);
    double unew = ustar >= 0 ? v : -v;
    // No flux out of a dry cell, none into a full one.
    const int up = unew > 0 ? f - 1 : f, down = unew > 0 ? f : f - 1;
    if (h_[up] <= s_.dry_depth || h_[down] >= s_.ceiling) unew = 0;
    un[f] = unew;
  }
  u.swap(un);
  // Mass (S1) with the new velocities, upwind active depth.
  for (int f = 1; f < n; ++f) q_[f] = u[f] * (u[f] > 0 ? a_[f - 1] : a_[f]);
  q_[0] = q_[n] = 0;
  for (int i = 0; i < n; ++i) h_[i] -= dt / dx_ * (q_[i + 1] - q_[i]);
  t_ += dt;
  ++steps_;
}

void ShallowGranularFlow::advance(double t1, const std::function<void(const ShallowGranularFlow&)>& after_step) {
  while (t_ < t1) {
    double dt = stable_dt();
    if (!(dt > 0) || !std::isfinite(dt)) dt = t1 - t_;
    // Land on t1 exactly, without a sliver of a last step.
    const double left = t1 - t_;
    if (left <= dt) {
      step(left);
      t_ = t1;
    } else {
      step(left < 2 * dt ? 0.5 * left : dt);
    }
    if (after_step) after_step(*this);
  }
}

}  // namespace grainscale::continuum::closure
