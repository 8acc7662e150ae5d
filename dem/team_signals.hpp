#pragma once
// Point-to-point waits between the threads of a parallel region, in place of barriers.
//
// A step's loops give each thread one range of spheres and the bodies that start in it
// (dem/work_split.hpp), so a thread depends on its neighbours for a few things only: the thread
// above follows spheres of the bodies that cross the cut, which the thread below turns (the drift);
// it completes its first spheres with the shares of pairs the thread below owns (the force loop);
// and the thread below sums bodies with spheres in the range above (the body sums). A barrier made
// both threads wait for the slower at each of those points, though only one of them needed the
// other, and only for part of its work; and a libgomp barrier costs 1.6-1.8 µs on this project's
// 2-vCPU VMs, an empty parallel region 3.2-3.7 µs, against ~0.4 µs for a line passed between the
// cores (docs/performance.md, "2026-12-05 (fifth session)"). Here thread t posts when it has done
// what the others need, at the point it is done, and a thread that needs it waits for that post
// only when it comes to the work that needs it.
//
// Posts carry a count that rises from one use to the next (the caller's epoch), so nothing is ever
// reset and a post from an earlier step cannot be mistaken for this one. Release on post and acquire
// on wait order the data written before the post before the reads after the wait.
//
// Only the timing changes: every sum has the same terms in the same order as with barriers.
//
// A meet (meet()) is the one place where every thread needs every other: twice a step, where thread 0
// does the step's serial part (Simulation::steps_in_region). It replaces the join of one parallel
// region and the fork of the next, so that the threads stay in one region for many steps.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include <omp.h>

namespace grainscale::dem {

class TeamSignals {
 public:
  /// Pauses a wait spins before it yields the core (see reserve()).
  static constexpr std::uint32_t kSpinsBeforeYield = 1u << 14;    // ~0.1-1 ms of pauses
  static constexpr std::uint32_t kSpinsOversubscribed = 1u << 6;  // more threads than processors

  TeamSignals() = default;
  // Posts are the state of one region only: a copy (of a simulation) starts with none.
  TeamSignals(const TeamSignals& o) : epoch_(o.epoch_) {}
  TeamSignals& operator=(const TeamSignals& o) {
    epoch_ = std::max(epoch_, o.epoch_);
    return *this;
  }

  /// Room for a team of `threads` (outside a parallel region). Keeps the posts of a team that fits.
  /// A team larger than the processors this process may run on spins only briefly before it yields:
  /// the thread waited for may be waiting for a core (the tests run 4 threads on 2). The processors
  /// are counted when the team size changes, not on every call: omp_get_num_procs() asks the kernel
  /// for the process's affinity (a sched_getaffinity system call, ~3 µs on this project's VMs), and
  /// the force loop reserves every step (in-process A/B on the clump bed: the step 2 % faster on 2
  /// threads and 2.5 % on 1 without it; docs/performance.md, "2026-12-05 (eighth session)").
  void reserve(int threads) {
    if (threads != counted_for_) {
      spins_before_yield_ = threads > omp_get_num_procs() ? kSpinsOversubscribed : kSpinsBeforeYield;
      counted_for_ = threads;
    }
    if (threads <= size_) return;
    slots_ = std::make_unique<Slot[]>(static_cast<std::size_t>(threads));
    size_ = threads;
  }
  /// Threads it has room for.
  int size() const { return size_; }
  /// How many pauses a wait spins before it yields the core (as chosen by the last reserve()).
  std::uint32_t spins_before_yield() const { return spins_before_yield_; }
  /// The next epoch to post and wait for (outside a parallel region, or by one thread while the
  /// others wait, once per use).
  std::uint64_t next_epoch() { return ++epoch_; }
  /// The first of `count` consecutive fresh epochs (for a region that runs many steps).
  std::uint64_t next_epochs(std::uint64_t count) {
    const std::uint64_t first = epoch_ + 1;
    epoch_ += count;
    return first;
  }

  /// Thread t has done this epoch's work that others wait for.
  void post(int t, std::uint64_t epoch) { slots_[t].value.store(epoch, std::memory_order_release); }

  /// Every thread of a team of `team` arrives; thread 0, once all have, runs `serial` and releases
  /// them. What the threads wrote before arriving is visible to `serial`, and what `serial` wrote to
  /// every thread after the meet. A barrier with a serial part, for the cost of a line passed each way
  /// (a libgomp barrier makes a futex call to wake its waiters: ~1 µs on this project's VMs).
  template <class Serial>
  void meet(int team, int t, std::uint64_t arrive, std::uint64_t release, Serial&& serial) {
    if (t == 0) {
      for (int u = 1; u < team; ++u) wait(u, arrive);
      serial();
      post(0, release);
    } else {
      post(t, arrive);
      wait(0, release);
    }
  }

  /// Waits until thread t has posted `epoch` (or a later one). Spins, as the step's other waits do,
  /// but yields the core after a while: with more threads than cores (the tests run 4 on 2) the
  /// thread waited for may need it.
  void wait(int t, std::uint64_t epoch) const {
    for (std::uint32_t spins = 0; slots_[t].value.load(std::memory_order_acquire) < epoch; ++spins) {
      if (spins < spins_before_yield_) {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      } else {
        std::this_thread::yield();
      }
    }
  }

 private:
  struct alignas(64) Slot {  // one line per thread: a post invalidates only its own
    std::atomic<std::uint64_t> value{0};
  };
  std::unique_ptr<Slot[]> slots_;
  int size_ = 0;
  std::uint32_t spins_before_yield_ = kSpinsBeforeYield;
  int counted_for_ = 0;  // the team size spins_before_yield_ was chosen for (0: none yet)
  std::uint64_t epoch_ = 0;
};

}  // namespace grainscale::dem
