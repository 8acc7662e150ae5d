#!/usr/bin/env bash
# Where the time step's memory traffic comes from (issue 11): callgrind's cache simulation of the timed
# steps of `grainscale bench`, as instructions and simulated cache misses per sphere-step for each stage
# of the step (drift, the two force passes, the wall contacts, body sums and kick, list builds, the
# stability monitor). See bench/README.md. Usage:
#   bench/run_cache_profile.sh [SCENARIO.yaml [SETTLED.h5]]
# Defaults: bench/clump_bed.yaml, settled into OUT/settled.h5 by the native build (bench --settled) if
# that file is missing; give the checkpoints of run_scaling.sh / run_clump_bed.sh to profile their beds.
#
# Why a second build: valgrind cannot decode the AVX-512 instructions of the native (-march=native)
# build on this kind of machine, so the profiled executable is built with PORTABLE_FLAGS (AVX2) into
# PROFILE_BUILD_DIR. Its memory accesses are those of the native build (same arrays, same order; only
# the width of the arithmetic differs); its instruction counts are not the native ones.
# What the figures are: callgrind simulates a D1 of 32 KiB and one last-level cache of LL_BYTES (no L2,
# no hardware prefetcher), so "LL misses" counts every 64-byte line the step brings from memory,
# whether or not a prefetcher would have hidden it. A stream the prefetchers follow costs little; a
# stage whose misses grow with the bed but are not sequential is where the latency goes.
# Environment knobs (all optional):
#   STEPS=20            profiled steps (after WARMUP untimed ones, which fill the simulated caches)
#   WARMUP=3
#   LL_BYTES=8388608    simulated last-level cache (this VM's effective L3 measures 4-12 MiB)
#   PORTABLE_FLAGS="-march=x86-64-v3"   PROFILE_BUILD_DIR=build-profile
#   SETTLE_THREADS=nproc  threads for the (native) settle when SETTLED.h5 is missing
#   BUILD_DIR=build  GRAINSCALE=path   the native grainscale used to settle
#   OUT=bench/out/cache_profile
# Cost: valgrind runs ~50x slower than native, the setup (the scenario's insertion, the checkpoint's
# load) included: 20 steps took ~70 s on the 10^5-sphere bed and ~2.5 min on the clump bed, after
# ~6 min for the portable build the first time.
set -euo pipefail
BENCH_NAME=cache_profile
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/lib_bench.sh"

SCENARIO="${1:-$HERE/clump_bed.yaml}"
OUT="${OUT:-$HERE/out/cache_profile}"
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
SETTLED="${2:-$OUT/settled.h5}"
STEPS="${STEPS:-20}"
WARMUP="${WARMUP:-3}"
LL_BYTES="${LL_BYTES:-8388608}"
PORTABLE_FLAGS="${PORTABLE_FLAGS:--march=x86-64-v3}"
PROFILE_BUILD_DIR="${PROFILE_BUILD_DIR:-$ROOT/build-profile}"
[[ "$PROFILE_BUILD_DIR" = /* ]] || PROFILE_BUILD_DIR="$ROOT/$PROFILE_BUILD_DIR"
SETTLE_THREADS="${SETTLE_THREADS:-$NCPU}"

[[ -f "$SCENARIO" ]] || die "no scenario file $SCENARIO"
[[ "$STEPS" =~ ^[1-9][0-9]*$ ]] || die "STEPS=$STEPS: give a whole number of steps, at least 1"
[[ "$WARMUP" =~ ^[0-9]+$ ]] || die "WARMUP=$WARMUP: give a whole number of steps, 0 or more"
[[ "$LL_BYTES" =~ ^[1-9][0-9]*$ ]] || die "LL_BYTES=$LL_BYTES: give the cache size in bytes"
if ! command -v valgrind >/dev/null || ! command -v callgrind_annotate >/dev/null; then
  say "valgrind not found; installing the Debian package 'valgrind'"
  apt_install valgrind
fi

if [[ ! -f "$SETTLED" ]]; then
  need_grainscale
  say "settling $SCENARIO into $SETTLED (native build, $SETTLE_THREADS threads)"
  run_logged "$OUT/settle.log" env OMP_NUM_THREADS="$SETTLE_THREADS" \
    "$GS" bench "$SCENARIO" --steps 1 --warmup 0 --threads "$SETTLE_THREADS" --settled "$SETTLED" \
    || die "settling failed: see $OUT/settle.log"
fi

say "building the portable executable in $PROFILE_BUILD_DIR ($PORTABLE_FLAGS)"
(cd "$ROOT" && cmake -S . -B "$PROFILE_BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DGRAINSCALE_NATIVE=OFF \
    -DCMAKE_CXX_FLAGS="$PORTABLE_FLAGS" >"$OUT/build.log" 2>&1 &&
  cmake --build "$PROFILE_BUILD_DIR" -j"$NCPU" --target grainscale >>"$OUT/build.log" 2>&1) \
  || die "portable build failed: see $OUT/build.log"
GS_PROFILE="$PROFILE_BUILD_DIR/studies/grainscale"

say "callgrind: $STEPS steps after $WARMUP, 1 thread, LL $LL_BYTES bytes (slow: see the header)"
rm -f "$OUT/callgrind.out"
valgrind --tool=callgrind --cache-sim=yes --D1=32768,8,64 --LL="$LL_BYTES",16,64 \
  --toggle-collect='*timed_steps*' --callgrind-out-file="$OUT/callgrind.out" \
  "$GS_PROFILE" bench "$SCENARIO" --steps "$STEPS" --warmup "$WARMUP" --threads 1 --settled "$SETTLED" \
  >"$OUT/profile.log" 2>&1 || die "valgrind run failed: see $OUT/profile.log"
callgrind_annotate --inclusive=yes --threshold=100 --show=Ir,D1mr,D1mw,DLmr,DLmw "$OUT/callgrind.out" \
  >"$OUT/inclusive.txt" 2>/dev/null || die "callgrind_annotate failed on $OUT/callgrind.out"

GS="$GS_PROFILE" machine_description | tee "$OUT/results.txt"
python3 - "$OUT/profile.log" "$OUT/inclusive.txt" "$STEPS" "$LL_BYTES" "$SCENARIO" <<'PY' | tee -a "$OUT/results.txt"
import re, sys
log, table, steps, ll, scenario = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
spheres = None
for line in open(log):
    m = re.match(r"problem: .*?, (\d+) spheres", line)
    if m: spheres = int(m.group(1))
if spheres is None: sys.exit("cache_profile: error: no 'problem:' line in " + log)
# Inclusive costs by function; a function's code inlined from other files is listed once more per
# file, with a smaller share: the largest entry is the function's whole inclusive cost.
cost = {}
for line in open(table):
    line = re.sub(r"\(\s*[0-9.]+%\)", "", line)
    m = re.match(r"\s*([0-9,.]+(?:\s+[0-9,.]+){4})\s+(\S.*)$", line)
    if not m: continue
    nums = [0 if v == "." else int(v.replace(",", "")) for v in m.group(1).split()]
    name = m.group(2)
    cost[name] = max(cost.get(name, [0] * 5), nums, key=lambda c: c[0])
def stage(pattern):
    best = [0] * 5
    for name, c in cost.items():
        if re.search(pattern, name) and c[0] > best[0]: best = c
    return best
# The stages as the step runs them (Simulation::steps_in_region): the drift, then one sweep over the
# spheres that finds the pairs, evaluates them and the wall contacts and completes each sphere's
# force (ForceField::pass), whose follow-up sums the bodies' forces and kicks them
# (Simulation::BodySums::run, called from within the sweep, so taken out of it here); list builds
# and the stability monitor come between steps. A function renamed in the step needs its pattern
# renamed here: a stage that matches nothing stops the script rather than reading as free.
stages = [  # (label, pattern); rows starting with two spaces are parts of the row above
    ("whole step", r"Simulation::run_steps\(unsigned long\)"),
    ("drift (half kick, move, spheres follow)", r"Simulation::drift_part\(int, int, double, unsigned long\) \["),
    ("force sweep (pairs, walls, completion)", r"ForceField::pass\(int, int,"),
    ("  of which pair evaluation", r"PairBatch<.*>::evaluate\(double\)"),
    ("  of which wall contacts", r"ForceField::add_wall_contacts<"),
    ("body sums and half kick", r"Simulation::BodySums::run\("),
    ("neighbour-list builds", r"Simulation::rebuild\("),
    ("stability monitor", r"Simulation::check_stability\(\)"),
]
rows = [(label, stage(p)) for label, p in stages]
for label, c in rows:
    if c[0] == 0 and label != "neighbour-list builds":  # (20 steps may hold no build)
        sys.exit(f"cache_profile: error: no cost for the stage '{label}' in {table}: a function renamed?")
# (A bed of clumps may sum its bodies as the sweep completes them, BodySums::ready: counted with the sums.)
ready = stage(r"Simulation::BodySums::ready\(")
rows = [(label, [a + b for a, b in zip(c, ready)] if label.startswith("body sums") else c) for label, c in rows]
sums = dict(rows)["body sums and half kick"]
rows = [(label, [a - b for a, b in zip(c, sums)] if label.startswith("force sweep") else c) for label, c in rows]
whole = rows[0][1]
listed = [c for label, c in rows[1:] if not label.startswith("  ")]
rest = [whole[k] - sum(c[k] for c in listed) for k in range(5)]
rows.append(("rest of the step", rest))
ss = spheres * steps
print(f"cache profile: {scenario}, {spheres} spheres, {steps} steps, 1 thread; simulated D1 32 KiB, LL {ll / 2**20:g} MiB")
print(f"per sphere-step: instructions, D1 misses, LL misses (lines from memory), bytes from memory")
print(f"{'stage':42s} {'instr':>8s} {'D1 miss':>8s} {'LL miss':>8s} {'bytes':>7s}")
for label, c in rows:
    d1 = (c[1] + c[2]) / ss; llm = (c[3] + c[4]) / ss
    print(f"{label:42s} {c[0] / ss:8.0f} {d1:8.2f} {llm:8.2f} {64 * llm:7.0f}")
PY
say "results: $OUT/results.txt (callgrind data: $OUT/callgrind.out; kcachegrind or callgrind_annotate read it)"
