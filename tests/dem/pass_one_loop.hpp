#pragma once
// Chooses the force loop for the life of the object, whatever the bed's size: that of beds beyond
// the caches (the chunked entry loop, the completion front right behind the pair front), or that of
// beds within them (the entry-by-entry loop, the completion in a second loop) (dem/force_field.hpp,
// beyond_cache_spheres), so that tests run both on small beds.
#include <cstddef>
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

}  // namespace grainscale::dem::testing
