#pragma once
// Cache lines at the cut between two threads' ranges, requested ahead of the loop that writes them.
//
// Each thread of a step takes one range of spheres and the bodies whose first sphere lies in it
// (Simulation::thread_bodies), so that nearly all of a sphere's data stays on one core. Near the cut
// some cannot: the thread below reads the first spheres of the range above as partners in its force
// loop, and the thread above writes them again in the next drift. A write to a line that another core
// has read waits for that core to give it up: ~450 ns on this project's 2-vCPU VMs (a cache-line
// round trip, docs/performance.md), for each of a few hundred lines per step, met one by one in a
// loop that has little else to do. Requested for writing a line at a time during the loop before,
// whose own arithmetic hides the transfers, they are this core's when the loop comes to them. (The
// body sums do the same for reading: Simulation::sum_bodies.)
//
// Only a hint: which lines are requested changes the time a step takes, never its numbers.

#include <cstddef>

#include "dem/prefetch.hpp"

namespace grainscale::dem {

/// The lines of up to kArrays arrays over the same range of elements, requested one line of each per call.
template <int kArrays>
class BoundaryLines {
 public:
  static constexpr std::size_t kLine = 64;

  BoundaryLines() = default;
  /// The first `bytes` bytes from each of `begin` but a null one.
  BoundaryLines(const void* const (&begin)[kArrays], std::size_t bytes) : lines_((bytes + kLine - 1) / kLine) {
    for (const void* array : begin) {
      if (array != nullptr) begin_[arrays_++] = static_cast<const char*>(array);
    }
  }

  /// Request the next line of each array, for writing (none once all have been requested).
  void fetch_next_for_write() {
    if (next_ == lines_) return;
    for (int a = 0; a < arrays_; ++a) prefetch_for_write(begin_[a] + kLine * next_);
    ++next_;
  }

 private:
  const char* begin_[kArrays] = {};
  int arrays_ = 0;
  std::size_t lines_ = 0, next_ = 0;
};

}  // namespace grainscale::dem
