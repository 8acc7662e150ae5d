#pragma once
// Which thread does which blocks of a loop: contiguous ranges, one per thread, of about equal time.
//
// Why not OpenMP's own schedules: the force loop ran `schedule(guided)` (balanced on the fly), which
// hands the first half of the blocks to whichever thread comes first and the rest in shrinking
// chunks to whichever is free, a different assignment every step. The drift, run just before, splits
// the spheres statically; so each step a large, varying share of the spheres' state was written by
// one core and read by the other. On a VM whose two vCPUs are far apart (a cache line takes ~480 ns
// to go and come back between them) that cost more than the second thread gained: the clump bed ran
// 2 threads at 0.86-0.98x of 1 thread, and 1.58-2.04x with fixed ranges (docs/performance.md,
// "2026-12-05 (later session)"). A static split keeps each sphere on one core from phase to phase
// but, equal in blocks, can give one thread most of the contacts (measured 2026-12-01: 15 against
// 19 M sphere-steps/s). Hence ranges cut by cost: each block's cost is estimated (its spheres, list
// entries, spheres near a wall), and each thread's share of the total follows its measured speed,
// so that what the estimate misses (a slower vCPU, costlier contacts in one half) is evened out.
// The step's other per-sphere and per-body loops (the drift, the body sums) take the same ranges
// (ForceField::thread_spheres, Simulation::thread_bodies): with equal counts of their own they moved
// the spheres between the two cuts from core to core every step (docs/performance.md, 2026-12-05).
//
// The split changes who computes a sum, never its terms or their order, so results are the same bit
// for bit for any split and thread count (the determinism tests); only the timing feeds back.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace grainscale::dem {

/// bounds (shares.size() + 1 values, bounds[0] = 0, bounds.back() = cost.size(), non-decreasing):
/// thread t takes blocks [bounds[t], bounds[t+1]). Cut t is placed at the block boundary nearest
/// to where the running cost reaches (shares[0] + ... + shares[t-1]) of the total, so thread t's cost
/// is its share of the total within one block's cost. `shares` are >= 0 and sum to 1.
inline void split_work(const std::vector<double>& cost, const std::vector<double>& shares,
                       std::vector<std::uint32_t>& bounds) {
  const std::size_t blocks = cost.size(), threads = shares.size();
  bounds.assign(threads + 1, 0);
  bounds[threads] = static_cast<std::uint32_t>(blocks);
  double total = 0;
  for (double c : cost) total += c;
  double running = 0, target = 0;
  std::size_t b = 0;
  for (std::size_t t = 1; t < threads; ++t) {
    target += shares[t - 1] * total;
    while (b < blocks && running + 0.5 * cost[b] < target) running += cost[b++];
    bounds[t] = static_cast<std::uint32_t>(b);
  }
}

/// The split of the force loop's blocks among a team, and its feedback: each thread reports the
/// seconds its blocks took; from a team's reports over enough steps, each thread's share of the next
/// split is made proportional to its speed (cost per second).
class WorkSplit {
 public:
  /// Splits `cost` (per block) for a team of `threads`, with the shares measured so far (equal for a
  /// new team size). Clears the reports.
  void split(const std::vector<double>& cost, int threads) {
    if (static_cast<int>(shares_.size()) != threads) shares_.assign(threads, 1.0 / threads);
    split_work(cost, shares_, bounds_);
    assigned_.assign(threads, 0.0);
    for (int t = 0; t < threads; ++t) {
      for (std::uint32_t b = bounds_[t]; b < bounds_[t + 1]; ++b) assigned_[t] += cost[b];
    }
    seconds_.assign(threads, Report{});
    steps_ = 0;
  }
  int threads() const { return static_cast<int>(shares_.size()); }
  std::size_t first(int t) const { return bounds_[t]; }
  std::size_t last(int t) const { return bounds_[t + 1]; }

  /// Thread t's time for its blocks this step (each thread writes its own cache line).
  void report(int t, double seconds) { seconds_[t].seconds += seconds; }
  /// After a step's reports are in (one thread, after the loop). A team of one has nothing to balance.
  void step_done() { steps_ += threads() > 1; }

  /// True when, over at least kSteps steps, the slowest thread took more than kTolerance longer than
  /// the mean: then each thread's share becomes proportional to its measured speed (at least
  /// kMinShare of an equal share, so that a thread slowed for a while, a preempted vCPU, keeps blocks
  /// to be measured on), and the caller splits again.
  bool rebalance() {
    const int threads = this->threads();
    if (threads < 2 || steps_ < kSteps) return false;
    double mean = 0, slowest = 0;
    for (const Report& r : seconds_) mean += r.seconds / threads, slowest = std::max(slowest, r.seconds);
    bool measured = mean > 0;
    for (int t = 0; t < threads; ++t) measured &= seconds_[t].seconds > 0 && assigned_[t] > 0;
    if (!measured || slowest <= (1 + kTolerance) * mean) {
      seconds_.assign(threads, Report{}), steps_ = 0;  // balanced: measure afresh
      return false;
    }
    double sum = 0;
    for (int t = 0; t < threads; ++t) sum += shares_[t] = assigned_[t] / seconds_[t].seconds;
    double floored = 0;
    for (double& s : shares_) floored += s = std::max(s / sum, kMinShare / threads);
    for (double& s : shares_) s /= floored;
    return true;
  }

 private:
  static constexpr int kSteps = 32;             // steps measured before a split is judged
  static constexpr double kTolerance = 0.03;    // the slowest thread's excess over the mean tolerated
  static constexpr double kMinShare = 0.25;     // the least share, as a fraction of an equal one
  struct alignas(64) Report {
    double seconds = 0;
  };
  std::vector<double> shares_;       // thread t's fraction of the total cost
  std::vector<std::uint32_t> bounds_{0, 0};
  std::vector<double> assigned_;     // the cost each thread was given
  std::vector<Report> seconds_;      // and the seconds it took, since the split
  int steps_ = 0;                    // steps measured since the split (teams of two or more)
};

/// Thread t's blocks [first, last) of `blocks` split equally: for a team that is not the size the
/// split was made for.
inline void equal_share(std::size_t blocks, int threads, int t, std::size_t& first, std::size_t& last) {
  first = blocks * static_cast<std::size_t>(t) / static_cast<std::size_t>(threads);
  last = blocks * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(threads);
}

}  // namespace grainscale::dem
