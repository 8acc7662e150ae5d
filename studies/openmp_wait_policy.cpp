#include "studies/openmp_wait_policy.hpp"

#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace grainscale::studies {

namespace {
// Valgrind preloads its vgpreload_*.so; it refuses to run /proc/self/exe again ("You cannot run ...
// directly"), and under it the wait policy does not matter.
bool under_valgrind() {
  const char* preload = std::getenv("LD_PRELOAD");
  return preload != nullptr && std::strstr(preload, "vgpreload") != nullptr;
}
}  // namespace

void prefer_short_openmp_spin(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (under_valgrind()) return;
  if (setenv("GOMP_SPINCOUNT", kDefaultSpinCount, 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
}

}  // namespace grainscale::studies
