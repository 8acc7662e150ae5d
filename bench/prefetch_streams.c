/* What a software prefetch does to a loop that reads many arrays in step, as the force loop's block
 * prefetch does (dem/force_field.cpp, prefetch_block): K arrays of doubles, ~400 MB in all (far past
 * the caches), read a line of each at a time, 8 lines of each per block; at the start of each block
 * the lines of the block D blocks ahead are requested with one kind of prefetch instruction, or none.
 * Prints GB/s read and ns per line, the best of 4 passes.
 *
 * Why it is here: on the twenty-first session's VM (AMD EPYC family 25 model 17, Zen 4) prefetcht0
 * (into the first-level cache) and prefetchnta halved the rate the hardware reached by itself, while
 * prefetcht1 and prefetcht2 (into the second level) kept most of it; and with no software prefetch
 * the rate fell past 16 arrays (the hardware follows only so many streams). docs/performance.md,
 * "twenty-first session", has the table.
 *
 * Build: cc -O2 bench/prefetch_streams.c -o prefetch_streams
 * Usage: prefetch_streams [K [D [KIND]]]   K arrays (default 16), D blocks ahead (default 8; 0: no
 * software prefetch), KIND t0, t1, t2 or nta (default t1). No arguments: the table for K = 8, 16, 24,
 * 32 and every kind. x86-64 only. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { kLineDoubles = 8, kBlockLines = 8, kPasses = 4 };
static const size_t kTotalBytes = 400u * 1000u * 1000u;

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void prefetch(const double* p, int kind) {
#if defined(__x86_64__)
  switch (kind) {
    case 0: __asm__ volatile("prefetcht0 (%0)" : : "r"(p)); break;
    case 1: __asm__ volatile("prefetcht1 (%0)" : : "r"(p)); break;
    case 2: __asm__ volatile("prefetcht2 (%0)" : : "r"(p)); break;
    default: __asm__ volatile("prefetchnta (%0)" : : "r"(p)); break;
  }
#else
  (void)p, (void)kind;
#endif
}

static const char* const kKinds[] = {"t0", "t1", "t2", "nta"};

/* One measurement: K arrays, D blocks ahead (0: none), prefetch kind. Returns ns per line. */
static double measure(int K, int D, int kind, double* gbs) {
  const size_t per = kTotalBytes / (size_t)K / sizeof(double);  /* doubles per array */
  const size_t block = (size_t)kBlockLines * kLineDoubles;
  double** a = malloc((size_t)K * sizeof *a);
  double** base = malloc((size_t)K * sizeof *base);
  if (a == NULL || base == NULL) return -1;
  for (int k = 0; k < K; ++k) {
    /* Each array starts at another offset within its page, as separately allocated arrays do. */
    base[k] = aligned_alloc(4096, per * sizeof(double) + 4096);
    if (base[k] == NULL) return -1;
    a[k] = base[k] + (size_t)(k * 7 % 64) * kLineDoubles % 512;
    memset(a[k], 1, per * sizeof(double));
  }
  double sum = 0, best = 1e30;
  for (int pass = 0; pass < kPasses; ++pass) {
    const double t0 = now();
    for (size_t i = 0; i + block <= per; i += block) {
      if (D > 0) {
        const size_t ahead = i + (size_t)D * block;
        if (ahead + block <= per)
          for (int k = 0; k < K; ++k)
            for (int l = 0; l < kBlockLines; ++l) prefetch(a[k] + ahead + (size_t)l * kLineDoubles, kind);
      }
      for (int l = 0; l < kBlockLines; ++l)
        for (int k = 0; k < K; ++k) {
          const double* p = a[k] + i + (size_t)l * kLineDoubles;
          sum += p[0] + p[3] + p[7];
        }
    }
    const double t = now() - t0;
    if (t < best) best = t;
  }
  for (int k = 0; k < K; ++k) free(base[k]);
  free(a), free(base);
  const double lines = (double)per * K / kLineDoubles;
  *gbs = lines * 64 / best / 1e9;
  return sum == 42 ? -1 : best / lines * 1e9;  /* (sum used, so that the loads are kept) */
}

static void row(int K, int D, int kind) {
  double gbs = 0;
  const double ns = measure(K, D, kind, &gbs);
  if (ns < 0) {
    fprintf(stderr, "prefetch_streams: could not allocate %d arrays of %zu MB\n", K, kTotalBytes / (size_t)K / 1000000);
    exit(1);
  }
  printf("%3d arrays  %2d blocks ahead  %-4s  %6.2f GB/s  %5.2f ns a line\n", K, D, D > 0 ? kKinds[kind] : "none",
         gbs, ns);
  fflush(stdout);
}

int main(int argc, char** argv) {
  if (argc > 1) {
    const int K = atoi(argv[1]), D = argc > 2 ? atoi(argv[2]) : 8;
    int kind = argc > 3 ? -1 : 1;
    if (argc > 3)
      for (int k = 0; k < 4; ++k)
        if (strcmp(argv[3], kKinds[k]) == 0) kind = k;
    if (K < 1 || K > 64 || D < 0 || kind < 0) {
      fprintf(stderr, "prefetch_streams: K must be 1..64, D >= 0 and KIND one of t0, t1, t2, nta\n");
      return 2;
    }
    row(K, D, kind);
    return 0;
  }
  const int ks[] = {8, 16, 24, 32};
  for (int i = 0; i < 4; ++i) {
    row(ks[i], 0, 1);
    for (int kind = 0; kind < 4; ++kind) row(ks[i], 8, kind);
  }
  return 0;
}
