#include "studies/openmp_wait_policy.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
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
/// The first field of /proc/loadavg, NaN if it cannot be read.
double load_average() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return NAN;
  double load = NAN;
  if (std::fscanf(f, "%lf", &load) != 1) load = NAN;
  std::fclose(f);
  return load;
}
}  // namespace

const char* spin_count_for(double load) { return load < kIdleLoad ? kIdleSpinCount : kDefaultSpinCount; }

void prefer_short_openmp_spin(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (under_valgrind()) return;
  if (setenv("GOMP_SPINCOUNT", spin_count_for(load_average()), 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
}

}  // namespace grainscale::studies
