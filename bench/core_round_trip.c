/* How far apart the machine's first two CPUs are: the time a cache line takes to go from one to the
 * other and back, in ns. Two threads, pinned one per CPU, hand a counter back and forth through one
 * atomic; the median of 5 batches of 20,000 round trips is printed.
 *
 * Why the benchmarks record it: on the VMs grainscale is measured on, this figure moved between ~100
 * and ~480 ns within minutes, and with it what a second thread gains (the clump bed, 14,000 spheres in
 * the caches, ran 2 threads at 1.8-1.9x of 1 near and 0.8x far before 2026-12-05; docs/performance.md).
 * A 2-thread figure without it cannot be compared with another.
 *
 * Build: cc -O2 -pthread bench/core_round_trip.c -o core_round_trip (lib_bench.sh does it). Prints
 * "nan" if there are fewer than two CPUs to pin to. */
#define _GNU_SOURCE
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

enum { kTrips = 20000, kBatches = 5 };

static _Atomic long counter;  /* odd: the second thread's turn; even: the first's */
static int cpus[2];

static int pin(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

static void* answer(void* unused) {
  (void)unused;
  (void)pin(cpus[1]);  /* unpinned if refused: it must answer either way */
  for (long i = 0; i < (long)kTrips * kBatches; ++i) {
    while (atomic_load_explicit(&counter, memory_order_acquire) != 2 * i + 1) {
    }
    atomic_store_explicit(&counter, 2 * i + 2, memory_order_release);
  }
  return NULL;
}

static double now_ns(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return 1e9 * (double)t.tv_sec + (double)t.tv_nsec;
}

static int by_value(const void* a, const void* b) {
  const double x = *(const double*)a, y = *(const double*)b;
  return (x > y) - (x < y);
}

int main(void) {
  cpu_set_t allowed;
  int found = 0;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0) {
    for (int c = 0; c < CPU_SETSIZE && found < 2; ++c) {
      if (CPU_ISSET(c, &allowed)) cpus[found++] = c;
    }
  }
  if (found < 2 || pin(cpus[0]) != 0) {
    puts("nan");
    return 0;
  }
  pthread_t other;
  if (pthread_create(&other, NULL, answer, NULL) != 0) {
    puts("nan");
    return 0;
  }
  double batch[kBatches];
  for (int b = 0; b < kBatches; ++b) {
    const double t0 = now_ns();
    for (long i = (long)b * kTrips; i < (long)(b + 1) * kTrips; ++i) {
      atomic_store_explicit(&counter, 2 * i + 1, memory_order_release);
      while (atomic_load_explicit(&counter, memory_order_acquire) != 2 * i + 2) {
      }
    }
    batch[b] = (now_ns() - t0) / kTrips;
  }
  pthread_join(other, NULL);
  qsort(batch, kBatches, sizeof batch[0], by_value);
  printf("%.0f\n", batch[kBatches / 2]);
  return 0;
}
