#pragma once
// Forces every OpenMP loop to run in parallel for the life of the object, however small the system
// (dem/parallel.hpp), so that thread-determinism tests exercise the parallel paths.
#include "dem/parallel.hpp"

namespace grainscale::dem::testing {

struct ParallelEverything {
  std::size_t saved = parallel_min_items();
  ParallelEverything() { parallel_min_items() = 0; }
  ~ParallelEverything() { parallel_min_items() = saved; }
};

}  // namespace grainscale::dem::testing
