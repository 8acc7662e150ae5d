#pragma once
// Eigen's dense module, as every file of grainscale includes it.
//
// Why not <Eigen/Dense> directly: GCC 12 with -march=native on an AVX-512 machine warns "'__Y' may be
// used uninitialized" inside Eigen's packet reductions (56 warnings in a full build, none ours). GCC's
// own avx512fintrin.h makes an undefined vector by self-initialisation (`__m256d __Y = __Y;`), which
// its -Wmaybe-uninitialized does not recognise once inlined (GCC bug 105593, fixed in GCC 13). The
// warning is off only for the lines of these headers (a diagnostic pragma applies by source
// location), so it still reports grainscale's own code; the intrinsics headers are read here first
// so that their lines fall inside the pragma, whichever file includes them later.
// (GCC only: Clang has no such warning and would warn about the unknown name.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif
#include <Eigen/Dense>
#pragma GCC diagnostic pop
#else
#include <Eigen/Dense>
#endif
