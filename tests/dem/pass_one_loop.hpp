#pragma once
// Chooses the force loop for the life of the object, whatever the bed's size: that of beds beyond
// the caches (the chunked entry loop, the completion front right behind the pair front), or that of
// beds within them (the entry-by-entry loop, the completion in a second loop) (dem/force_field.hpp,
// beyond_cache_spheres), so that tests run both on small beds.
#include <catch2/catch.hpp>

#include <cstddef>
#include <cstring>
#include <limits>

#include "dem/force_field.hpp"

namespace grainscale::dem::testing {

struct PassOneLoop {
  std::size_t saved = beyond_cache_spheres();
  explicit PassOneLoop(bool chunked) {
    beyond_cache_spheres() = chunked ? 0 : std::numeric_limits<std::size_t>::max();
  }
  ~PassOneLoop() { beyond_cache_spheres() = saved; }
  PassOneLoop(const PassOneLoop&) = delete;
  PassOneLoop& operator=(const PassOneLoop&) = delete;
};

/// `run(threads, beyond_the_caches)` returns a run's end state as a vector of plain values; the runs
/// with the loops of beds beyond the caches, on 1 to `most_threads` threads, must end on the state of
/// the run with the loops of beds within them, on 1 thread, bit for bit.
template <class Run>
void check_same_beyond_the_caches(Run&& run, int most_threads) {
  const auto within = run(1, false);
  for (int threads = 1; threads <= most_threads; ++threads) {
    INFO(threads << " threads");
    const auto beyond = run(threads, true);
    REQUIRE(beyond.size() == within.size());
    CHECK(std::memcmp(beyond.data(), within.data(), within.size() * sizeof(within[0])) == 0);
  }
}

}  // namespace grainscale::dem::testing
