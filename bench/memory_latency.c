/* How long a load waits on this machine, by how much memory a program walks: the load-to-use time of
 * a dependent chain of loads (a pointer chase) over working sets from 32 KiB to 256 MiB, in ns.
 *
 * Why the benchmarks record it: the cache sizes the system reports do not say how far the fast
 * caches reach, and grainscale's figures move with that reach (its cost per sphere-step steps up
 * where a bed leaves the second level: the scaling beds' 10^3 -> 10^5 ratio; the clump bed speeds up
 * by more than 2x on two cores, each core's cache holding half of it: docs/performance.md). On the
 * Intel VM of 2026-12-07 sysfs reports a 480 MiB L3, yet a load waits ~5 ns up to 1 MiB, ~40 ns from
 * 4 to 8 MiB and 130-250 ns from 16 MiB on; a 2026-12-04 AMD VM (a 32 MiB L3 by sysfs) measured 4 ns
 * at 256 KiB, 12-18 ns from 1 to 4 MiB and 126-228 ns from 8 MiB.
 *
 * Method: one pointer per 64-byte line, the lines linked in one cycle through all of them in a
 * random order (Sattolo's algorithm: a single cycle, so the chase visits every line before it
 * repeats, and no hardware prefetcher can guess the next line); the buffer is written first (its
 * pages are resident), the chase warmed over one full cycle, then timed over at least 2^21 loads.
 * Each size's figure is the fastest of 3 timings. Pages are the system's default (transparent huge
 * pages only where the system's setting gives them unasked), as grainscale's arrays get them, so the
 * figures include the page walks a step pays.
 *
 * Build: cc -O2 bench/memory_latency.c -o memory_latency (lib_bench.sh does it).
 * Usage: memory_latency [KIB...]   (default 32 256 1024 2048 4096 8192 16384 65536 262144)
 * Prints one line: "32 KiB 1.6 ns, 256 KiB 5.0 ns, ..." ("?" for a size it could not allocate).
 * memory_latency --check: builds cycles of several sizes and exits 1 unless each is one cycle
 * through every line (the property the figures rest on). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct Line {
  struct Line* next;
  char pad[64 - sizeof(struct Line*)];
} Line;

/* xorshift64*: a fixed seed, so every run walks the same order */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t next_random(void) {
  rng_state ^= rng_state >> 12, rng_state ^= rng_state << 25, rng_state ^= rng_state >> 27;
  return rng_state * 0x2545F4914F6CDD1Dull;
}

/* Links lines[0..n) into one cycle in a random order (Sattolo: j < i, never j == i). */
static void link_one_cycle(Line* lines, size_t n, size_t* order) {
  for (size_t i = 0; i < n; ++i) order[i] = i;
  for (size_t i = n - 1; i > 0; --i) {
    const size_t j = (size_t)(next_random() % i);
    const size_t t = order[i];
    order[i] = order[j], order[j] = t;
  }
  /* order is now a cyclic permutation: line k's successor is order[k] */
  for (size_t k = 0; k < n; ++k) lines[k].next = &lines[order[k]];
}

static double now_ns(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return 1e9 * (double)t.tv_sec + (double)t.tv_nsec;
}

/* The chase's end, kept so that the compiler cannot drop the loads. */
static volatile uintptr_t sink;

static double chase_ns(size_t kib) {
  const size_t n = kib * 1024 / sizeof(Line);
  if (n < 2) return -1;
  Line* lines = NULL;
  if (posix_memalign((void**)&lines, 64, n * sizeof(Line)) != 0) return -1;
  size_t* order = malloc(n * sizeof(size_t));
  if (order == NULL) {
    free(lines);
    return -1;
  }
  memset(lines, 0, n * sizeof(Line));
  link_one_cycle(lines, n, order);
  free(order);
  const Line* p = &lines[0];
  for (size_t i = 0; i < n; ++i) p = p->next; /* warm: one full cycle */
  const size_t loads = n > ((size_t)1 << 21) ? n : ((size_t)1 << 21);
  double best = -1;
  for (int round = 0; round < 3; ++round) {
    const double t0 = now_ns();
    for (size_t i = 0; i < loads; ++i) p = p->next;
    const double ns = (now_ns() - t0) / (double)loads;
    if (best < 0 || ns < best) best = ns;
  }
  sink = (uintptr_t)p;
  free(lines);
  return best;
}

/* 0 if the lines of a buffer of n lines form one cycle through all of them. */
static int check_cycle(size_t n) {
  Line* lines = calloc(n, sizeof(Line));
  size_t* order = malloc(n * sizeof(size_t));
  char* seen = calloc(n, 1);
  int bad = lines == NULL || order == NULL || seen == NULL;
  if (!bad) {
    link_one_cycle(lines, n, order);
    const Line* p = &lines[0];
    for (size_t i = 0; i < n && !bad; ++i) {
      const size_t k = (size_t)(p - lines);
      bad = k >= n || seen[k];
      if (!bad) seen[k] = 1;
      p = p->next;
    }
    bad = bad || p != &lines[0]; /* back at the start after exactly n steps */
  }
  free(lines), free(order), free(seen);
  return bad;
}

int main(int argc, char** argv) {
  if (argc == 2 && strcmp(argv[1], "--check") == 0) {
    const size_t sizes[] = {2, 3, 7, 64, 1000, 4096, 100003};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; ++s) {
      if (check_cycle(sizes[s]) != 0) {
        printf("not one cycle through %zu lines\n", sizes[s]);
        return 1;
      }
    }
    puts("one cycle through every line, for every size checked");
    return 0;
  }
  static const size_t defaults[] = {32, 256, 1024, 2048, 4096, 8192, 16384, 65536, 262144};
  const int count = argc > 1 ? argc - 1 : (int)(sizeof defaults / sizeof defaults[0]);
  for (int i = 0; i < count; ++i) {
    size_t kib = 0;
    if (argc == 1) {
      kib = defaults[i];
    } else {
      char* end = NULL;
      const unsigned long long v = strtoull(argv[i + 1], &end, 10);
      if (end == argv[i + 1] || *end != '\0' || v < 1 || v > (1ull << 24)) {
        fprintf(stderr, "memory_latency: '%s' is not a size in KiB from 1 to 16777216\n", argv[i + 1]);
        return 2;
      }
      kib = (size_t)v;
    }
    const double ns = chase_ns(kib);
    const char* sep = i + 1 < count ? ", " : "\n";
    if (kib >= 1024 && kib % 1024 == 0) {
      printf("%zu MiB ", kib / 1024);
    } else {
      printf("%zu KiB ", kib);
    }
    if (ns < 0) {
      printf("?%s", sep);
    } else {
      printf("%.1f ns%s", ns, sep);
    }
    fflush(stdout);
  }
  return 0;
}
