#!/bin/sh
# Whether loops the project relies on GCC to vectorise are vectorised in a compiled library or object:
# every out-of-line function whose mangled name matches FUNCTIONS must hold at least MIN
# instructions matching PACKED (packed, several lanes each). Called by batches_vectorised.sh and
# follow_vectorised.sh, which say what they check and why.
# Usage: packed_in_functions.sh OBJDUMP LIB MIN FUNCTIONS PACKED WHAT
#   FUNCTIONS: an awk regex for "<mangled name>:" lines; PACKED: an awk regex for an instruction;
#   WHAT: what PACKED counts, for the messages ("packed square roots").
set -eu
objdump=$1 lib=$2 min=$3 functions=$4 packed=$5 what=$6
"$objdump" -d --no-show-raw-insn "$lib" | awk -v min="$min" -v functions="$functions" -v packed="$packed" -v what="$what" '
  /^[0-9a-f]+ <.*>:$/ {
    fn = $2
    if (fn ~ functions) { seen[fn] = 1; count[fn] += 0 }
  }
  $0 ~ packed { if (fn in seen) count[fn]++ }
  END {
    n = 0; bad = 0
    for (f in count) { n++; printf "%d %s in %s\n", count[f], what, f; if (count[f] < min) bad = 1 }
    if (n == 0) { printf "no function out of line matches %s\n", functions; exit 1 }
    if (bad) { printf "fewer than %d %s in some function: not vectorised?\n", min, what; exit 1 }
  }'
