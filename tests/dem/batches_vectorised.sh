#!/bin/sh
# The batched contact models are vectorised in the compiled library (dem/pair_batch.hpp,
# wall_batch.hpp): their square roots must be packed ones (sqrtpd / vsqrtpd), several contacts per
# instruction. Until 2026-12-07 they were not in any build without AVX-512: GCC kept a division a
# select discards inside a branch and, assuming floating-point operations may trap, could not
# if-convert it (CMakeLists.txt, -fno-trapping-math); the AVX2 build ran the contact models one
# contact at a time, 27-34 % slower on the clump bed, and nothing said so.
# Every out-of-line PairBatch / WallBatch evaluate must hold at least MIN packed square roots (GCC
# 12.2, AVX2 and AVX-512 builds: 10 to 16; without -fno-trapping-math on AVX2: 0).
# Usage: batches_vectorised.sh OBJDUMP LIB MIN
set -eu
exec sh "$(dirname "$0")/packed_in_functions.sh" "$1" "$2" "$3" \
  '^<_ZN10grainscale3dem(9PairBatch|9WallBatch)I.*8evaluateEd>:$' '\tv?sqrtpd' 'packed square roots'
