#include "dem/progress.hpp"

#include <cmath>
#include <cstdio>

namespace grainscale::dem {

Progress::Progress(double sim_start, double sim_end, double interval_s, Sink sink)
    : start_(sim_start), end_(sim_end), interval_(interval_s), sink_(std::move(sink)), t0_(Clock::now()), last_(t0_) {}

double Progress::elapsed() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }

std::string Progress::format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--:--";
  const long t = std::lround(s);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return buf;
}

void Progress::update(double sim_time, std::uint64_t steps, std::size_t particles, bool force, double dt) {
  const auto now = Clock::now();
  if (first_) {
    steps0_ = steps;
    first_ = false;
  }
  if (!force && std::chrono::duration<double>(now - last_).count() < interval_) return;
  last_ = now;
  const double wall = std::chrono::duration<double>(now - t0_).count();
  const double done = (sim_time - start_) / (end_ - start_);
  const double rate = wall > 0 ? (sim_time - start_) / wall : 0;  // simulated s per wall s
  const double eta = rate > 0 ? (end_ - sim_time) / rate : -1;
  const double sphere_steps = wall > 0 ? static_cast<double>(steps - steps0_) * particles / wall : 0;
  sink_(line(sim_time, end_, done, dt, rate, sphere_steps, eta));
}

std::string Progress::line(double sim_time, double sim_end, double done, double dt, double sim_per_wall_s,
                           double sphere_steps_per_s, double eta) {
  char step[48] = "";
  if (dt > 0) std::snprintf(step, sizeof step, " | step %.4g s", dt);
  char text[320];
  std::snprintf(text, sizeof text, "t = %.4g / %.4g s (%5.1f %%)%s | %.3g sim s per wall h | %.3g M sphere-steps/s | ETA %s",
                sim_time, sim_end, 100 * done, step, sim_per_wall_s * 3600, sphere_steps_per_s / 1e6,
                format_duration(eta).c_str());
  return text;
}

}  // namespace grainscale::dem
