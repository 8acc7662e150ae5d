#pragma once
// Cache lines requested ahead of the loop that will use them, by statements the compiler keeps.
//
// GCC takes __builtin_prefetch to have no side effects. A lambda that does nothing but prefetch is
// then found pure, and its call, whose result nobody uses, dead code: GCC 12 (-O1 and above) dropped
// every prefetch of the force loop's `prefetch_ahead` and `prefetch_block` lambdas that way, from
// 2026-12-04 (d080acb, when the partner prefetch moved into a lambda) to 2026-12-06 (the block
// prefetch was never in a binary; docs/performance.md, "fifteenth session"). A loop that also
// loads or stores (the body sums' fetch ahead) kept its prefetches, which is why nothing showed.
// An asm statement marked volatile is never removed; off x86-64 the builtin is what there is. The
// address goes in a register, not as a memory operand: no object is named, so none need exist.
//
// Only a hint: a prefetch changes the time a loop takes, never its numbers. It does not fault, so
// it may name any address (a line's start before an array's first element, one past its end).

#include <cstdint>

namespace grainscale::dem {

/// Ask for the cache line holding `p`, to be read.
inline void prefetch_for_read(const void* p) {
#if defined(__x86_64__)
  asm volatile("prefetcht0 (%0)" : : "r"(p));
#else
  __builtin_prefetch(p, 0);
#endif
}

/// Ask for the cache line holding `p`, to be written: held exclusively, so that the store need not
/// ask again (where the CPU has PREFETCHW; else as for reading, as GCC's builtin does).
inline void prefetch_for_write(const void* p) {
#if defined(__x86_64__) && defined(__PRFCHW__)
  asm volatile("prefetchw (%0)" : : "r"(p));
#elif defined(__x86_64__)
  asm volatile("prefetcht0 (%0)" : : "r"(p));
#else
  __builtin_prefetch(p, 1);
#endif
}

/// Ask for the cache line holding `p` to be brought into the second-level cache, for a use some
/// hundreds of nanoseconds off, read or written. Why not into the first level (prefetcht0,
/// prefetchw) for lines wanted that far ahead: those hold one of the first level's few miss buffers
/// until the line arrives, and a stream of them starves the loop's own loads and the hardware's
/// prefetchers. bench/prefetch_streams.c on AMD EPYC (Zen 4, 2026-12-07), 16 arrays read in step,
/// each line requested 8 blocks ahead: 11.3 GB/s with prefetcht0, 25.1 with prefetcht1 (34.2 with
/// none, but past 16 arrays the hardware loses track: 24 arrays 18.7, and 20.2 with prefetcht1).
/// The force loop's block prefetch: docs/performance.md, "twenty-first session". A line that came
/// this way and that no other core holds comes exclusive, so a store to it needs no second request.
inline void prefetch_to_l2(const void* p) {
#if defined(__x86_64__)
  asm volatile("prefetcht1 (%0)" : : "r"(p));
#else
  __builtin_prefetch(p, 0, 2);
#endif
}

/// `request` for every 64-byte line of [from, to) (a lambda, so that it is inlined).
template <class T, class Request>
inline void each_line(const T* from, const T* to, Request request) {
  const char* line = reinterpret_cast<const char*>(reinterpret_cast<std::uintptr_t>(from) & ~std::uintptr_t{63});
  const char* const end = reinterpret_cast<const char*>(to);
  for (; line < end; line += 64) request(line);
}

/// Every 64-byte line of [from, to), into the second level (prefetch_to_l2).
template <class T>
inline void prefetch_lines_to_l2(const T* from, const T* to) {
  each_line(from, to, [](const char* line) { prefetch_to_l2(line); });
}

/// Every 64-byte line of [from, to), to be read or (`for_write`) written, into the first level.
template <class T>
inline void prefetch_lines(const T* from, const T* to, bool for_write = false) {
  if (for_write) {
    each_line(from, to, [](const char* line) { prefetch_for_write(line); });
  } else {
    each_line(from, to, [](const char* line) { prefetch_for_read(line); });
  }
}

}  // namespace grainscale::dem
