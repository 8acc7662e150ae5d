#pragma once
// Progress lines for long runs: simulated time, percentage, the time step, speed and ETA, at most
// every `interval` seconds of wall-clock time. Printed to stderr and to the run's log.
//
// The step is in the line because under the step control (dem/step_control.hpp) it changes during
// a run: the log reports each fall by a fifth, not the climbs back, and the speed in simulated
// seconds per hour is the step times the steps per second, so a slow stretch is read off the line.
#include <chrono>
#include <functional>
#include <string>

namespace grainscale::dem {

class Progress {
 public:
  using Sink = std::function<void(const std::string&)>;
  Progress(double sim_start, double sim_end, double interval_s, Sink sink);
  /// Call often; prints only when `interval` has passed (or when forced). `dt`: the time step now
  /// (0: not shown).
  void update(double sim_time, std::uint64_t steps, std::size_t particles, bool force = false, double dt = 0);
  /// The line update() prints, from its figures: done as a fraction, the speed in simulated s per
  /// wall-clock s, eta in s (< 0: unknown), dt 0: the step not shown.
  static std::string line(double sim_time, double sim_end, double done, double dt, double sim_per_wall_s,
                          double sphere_steps_per_s, double eta);
  double elapsed() const;

  static std::string format_duration(double seconds);

 private:
  using Clock = std::chrono::steady_clock;
  double start_, end_, interval_;
  Sink sink_;
  Clock::time_point t0_, last_;
  std::uint64_t steps0_ = 0;
  bool first_ = true;
};

}  // namespace grainscale::dem
