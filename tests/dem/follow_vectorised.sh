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
objdump=$1 lib=$2 min=$3
"$objdump" -d --no-show-raw-insn "$lib" | awk -v min="$min" '
  /^[0-9a-f]+ <.*>:$/ {
    fn = $2
    if (fn ~ /^<_ZN10grainscale3dem12_GLOBAL__N_111follow_spanI/) { seen[fn] = 1; count[fn] += 0 }
  }
  /\tv?mulpd/ { if (fn in seen) count[fn]++ }
  END {
    n = 0; bad = 0
    for (f in count) { n++; printf "%d packed multiplications in %s\n", count[f], f; if (count[f] < min) bad = 1 }
    if (n == 0) { print "no follow_span found out of line"; exit 1 }
    if (bad) { printf "fewer than %d in some follow_span: the sphere follow not vectorised?\n", min; exit 1 }
  }'
