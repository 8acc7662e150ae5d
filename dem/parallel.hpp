#pragma once
// When a loop is worth a parallel region. Forking and joining OpenMP threads costs microseconds
// (tens of microseconds when idle threads sleep, OMP_WAIT_POLICY=passive), so loops over fewer items
// than this run serially: a 7-sphere clump test took 173 s instead of 2 s without it. Results do not
// depend on the choice (each element is written by one thread, reductions are exact), which the
// determinism tests check by setting it to 0 (everything parallel).
#include <cstddef>

namespace grainscale::dem {

inline std::size_t& parallel_min_items() {
  static std::size_t items = 1024;
  return items;
}

}  // namespace grainscale::dem
