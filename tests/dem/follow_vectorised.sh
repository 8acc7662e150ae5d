#!/bin/sh
# The drift's sphere follow is vectorised in the compiled library (dem/simulation.cpp, follow_span):
# its multiplications must be packed ones (mulpd / vmulpd), several spheres per instruction. Written
# a sphere at a time, with a body's angular velocity copied whole into the sphere's, GCC 12 left the
# loop scalar ("more than one data ref in stmt"); so it does with the arrays' aliasing checked at run
# time (more checks than it allows: follow_span inlined, its restrict qualifiers lost).
# Every out-of-line follow_span must hold at least MIN packed multiplications (GCC 12.2, AVX-512
# build: 48 to 66; the angular velocity copied whole: 0; follow_span inlined: none out of line).
# Usage: follow_vectorised.sh OBJDUMP LIB MIN
set -eu
exec sh "$(dirname "$0")/packed_in_functions.sh" "$1" "$2" "$3" \
  '^<_ZN10grainscale3dem12_GLOBAL__N_111follow_spanI' '\tv?mulpd' 'packed multiplications'
