#include "continuum/ssp_rk3.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace grainscale::continuum {

SspRk3::SspRk3(const Model& model, IntegratorSettings settings) : model_(model), settings_(std::move(settings)) {
  const std::size_t n = model.state_size();
  k_.resize(n);
  u1_.resize(n);
  u2_.resize(n);
}

void SspRk3::advance(double t0, double t1, std::vector<double>& c) {
  const std::size_t n = c.size();
  if (n != model_.state_size()) {
    throw std::invalid_argument("ssp_rk3: the vector has " + std::to_string(n) + " entries, the model's state " +
                                std::to_string(model_.state_size()) + " (advance Model::state(t, c), not c, for a moving " +
                                "surface or the depth-averaged model)");
  }
  double t = t0;
  long steps = 0;
  while (t < t1) {
    // Steady flows give a constant rate bound; it is cheap enough to recompute for unsteady ones.
    const double rate = model_.state_max_rate(t, c);
    double dt = rate > 0 ? settings_.cfl / rate : t1 - t;
    if (settings_.max_dt > 0) dt = std::min(dt, settings_.max_dt);
    // Equal steps to the stop time: no sliver step at the end.
    const double left = t1 - t;
    const double count = std::ceil(left / dt * (1 - 1e-12));
    dt = left / std::max(1.0, count);
    if (++steps > settings_.max_steps) throw std::runtime_error("ssp_rk3: more than max_steps steps");

    model_.state_rhs(t, c, k_);
    for (std::size_t j = 0; j < n; ++j) u1_[j] = c[j] + dt * k_[j];
    model_.state_rhs(t + dt, u1_, k_);
    for (std::size_t j = 0; j < n; ++j) u2_[j] = 0.75 * c[j] + 0.25 * (u1_[j] + dt * k_[j]);
    model_.state_rhs(t + 0.5 * dt, u2_, k_);
    for (std::size_t j = 0; j < n; ++j) c[j] = c[j] / 3 + 2.0 / 3 * (u2_[j] + dt * k_[j]);
    stats_.rhs_evaluations += 3;
    ++stats_.steps;
    t = count <= 1 ? t1 : t + dt;  // land exactly on the stop time
  }
}

}  // namespace grainscale::continuum
