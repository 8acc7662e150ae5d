#pragma once
// Stores that go to memory without first reading the line (non-temporal, write-combining).
//
// An ordinary store to a line that is not in the caches first reads it from memory (a read for
// ownership), only to overwrite it. A loop that writes whole arrays of a bed beyond the caches pays
// that read on every line, a third more traffic for an array it only writes. These stores fill a
// write-combining buffer instead and send the whole line when it is complete: written in order,
// element after element, each line is sent once and never read. The line is not left in the caches,
// so only where the next reader will find it gone anyway (a bed beyond the caches); and they are
// ordered weakly, so the writer must call stream_fence() before another thread may read what it
// wrote.

#include <bit>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "dem/vec3.hpp"

namespace grainscale::dem {

/// *to = v, bypassing the caches where the CPU can (else an ordinary store).
inline void stream_store(Vec3* to, const Vec3& v) {
#if defined(__x86_64__)
  long long* const out = reinterpret_cast<long long*>(to);
  _mm_stream_si64(out, std::bit_cast<long long>(v.x));
  _mm_stream_si64(out + 1, std::bit_cast<long long>(v.y));
  _mm_stream_si64(out + 2, std::bit_cast<long long>(v.z));
#else
  *to = v;
#endif
}

/// Makes this thread's stream_store()s visible before its later stores (a signal to another thread).
inline void stream_fence() {
#if defined(__x86_64__)
  _mm_sfence();
#endif
}

}  // namespace grainscale::dem
