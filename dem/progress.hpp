#pragma once
// Progress lines for long runs: simulated time, percentage, speed and ETA, at most every
// `interval` seconds of wall-clock time. Printed to stderr and to the run's log.
#include <chrono>
#include <functional>
#include <string>

namespace grainscale::dem {

class Progress {
 public:
  using Sink = std::function<void(const std::string&)>;
  Progress(double sim_start, double sim_end, double interval_s, Sink sink);
  /// Call often; prints only when `interval` has passed (or when forced).
  void update(double sim_time, std::uint64_t steps, std::size_t particles, bool force = false);
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
