#include "studies/openmp_wait_policy.hpp"

#include <unistd.h>

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
/// Runnable tasks now, from /proc/loadavg ("0.20 0.80 1.21 1/78 11492": the 1 of 1/78); 0 if unreadable.
int runnable_tasks() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return 0;
  double a = 0, b = 0, c = 0;
  int runnable = 0, total = 0;
  if (std::fscanf(f, "%lf %lf %lf %d/%d", &a, &b, &c, &runnable, &total) != 5) runnable = 0;
  std::fclose(f);
  return runnable;
}
}  // namespace

const char* spin_count_for(int runnable) { return runnable == 1 ? kIdleSpinCount : kDefaultSpinCount; }

void choose_openmp_spin(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (under_valgrind()) return;
  if (setenv("GOMP_SPINCOUNT", spin_count_for(runnable_tasks()), 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only on failure: go on as we are
}

}  // namespace grainscale::studies
