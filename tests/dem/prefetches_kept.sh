#!/bin/sh
# The force loop's prefetches are in the compiled library (dem/prefetch.hpp says how GCC dropped
# them for two days: the source asked for them, the binary had 6 per force pass, all near walls).
# Each instantiation of ForceField::pass_with must hold at least MIN prefetch instructions: the
# partner's 7, a loop for each of the block's 19 or 20 arrays ahead, the wall slots' and hints' 3
# (GCC 12.2: 35, 36, 35; without the partner's 28, without the block's 16: MIN is 30).
# Usage: prefetches_kept.sh OBJDUMP LIB MIN
set -eu
objdump=$1 lib=$2 min=$3
"$objdump" -d --no-show-raw-insn "$lib" | awk -v min="$min" '
  /^[0-9a-f]+ <.*>:$/ { fn = $2; if (fn ~ /^<_ZN10grainscale3dem10ForceField9pass_with/) { seen[fn] = 1; count[fn] += 0 } }
  /\tprefetch/ { if (fn in seen) count[fn]++ }
  END {
    n = 0; bad = 0
    for (f in count) { n++; printf "%d prefetch instructions in %s\n", count[f], f; if (count[f] < min) bad = 1 }
    if (n == 0) { print "no ForceField::pass_with found"; exit 1 }
    if (bad) { printf "fewer than %d in some force pass: prefetches dropped by the compiler?\n", min; exit 1 }
  }'
