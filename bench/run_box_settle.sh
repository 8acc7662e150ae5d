#!/usr/bin/env bash
# "Box settle" benchmark: grainscale vs LIGGGHTS 3.8 (Debian package) on the same problem.
# See bench/README.md. Usage (from anywhere):
#   bench/run_box_settle.sh
# Environment knobs (all optional):
#   STEPS=20000        timed steps after settling
#   COUNTS="1 2"       grainscale OpenMP threads / LIGGGHTS MPI processes to time
#   REPEATS=2          timed runs per code and count; the fastest is reported
#   IDLE_WAIT=600      seconds to wait, before each timed run, for the machine to be idle
#   IDLE_MAX=10        % of all CPUs that other processes may use and still count as idle
#   OUT=bench/out      logs (grainscale_*.log, liggghts_*.log) and results.txt
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/.." && pwd)"
OUT="${OUT:-$HERE/out}"
YAML="$HERE/box_settle.yaml"
LIG_IN="$HERE/liggghts/in.box_settle"

STEPS="${STEPS:-20000}"
COUNTS="${COUNTS:-1 2}"
REPEATS="${REPEATS:-2}"
IDLE_WAIT="${IDLE_WAIT:-600}"
IDLE_MAX="${IDLE_MAX:-10}"

BENCH_NAME=box_settle
# die, say, need_liggghts, need_grainscale, wait_idle, run_logged (bench/lib_bench.sh)
source "$HERE/lib_bench.sh"

[[ -f "$YAML" ]] || die "missing $YAML"
[[ -f "$LIG_IN" ]] || die "missing $LIG_IN"
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"  # (LIGGGHTS runs in OUT)
need_liggghts    # LIGGGHTS from Debian, installed if missing; MPIRUN
need_grainscale  # GS, built into build/ if missing

rm -f "$OUT"/grainscale_t*_r*.log* "$OUT"/liggghts_np*_r*.log* "$OUT/results.txt"

# ---------------------------------------------------------------- 1. grainscale: settled state
say "grainscale: settling once with 'dem' for the settled-state check (kinetic energy) ..."
GS_STATE_DIR="$OUT/grainscale_settled"
rm -rf "$GS_STATE_DIR"
if ! "$GS" dem "$YAML" --out "$GS_STATE_DIR" --threads 1 >"$OUT/grainscale_settled.log" 2>&1; then
  say "warning: 'grainscale dem' failed (see $OUT/grainscale_settled.log); the settled-state check will lack it"
fi
snap="$(ls "$GS_STATE_DIR"/snapshots/*.h5 2>/dev/null | tail -1 || true)"
if [[ -n "$snap" ]]; then
  python3 "$HERE/h5_bed.py" "$snap" >"$GS_STATE_DIR/bed.txt" 2>"$OUT/h5_bed.err" \
    || say "warning: could not read the bed height from $snap (see $OUT/h5_bed.err)"
fi

# ---------------------------------------------------------------- 2. grainscale: timed
for n in $COUNTS; do
  for r in $(seq 1 "$REPEATS"); do
    wait_idle
    log="$OUT/grainscale_t${n}_r${r}.log"
    say "grainscale bench, $n thread(s), repeat $r: settle + $STEPS timed steps -> $log"
    run_logged "$log" "$GS" bench "$YAML" --steps "$STEPS" --threads "$n" \
      || die "grainscale bench failed (exit $?); see $log"
    grep -E '^threads' "$log" >&2 || die "no 'threads N:' line in $log"
  done
done

# the problem as grainscale set it up: sphere count, time step, largest radius -> skin
first_log="$OUT/grainscale_t$(echo $COUNTS | awk '{print $1}')_r1.log"
read -r GS_N GS_DT < <(python3 - "$first_log" <<'PY'
import re, sys
t = open(sys.argv[1]).read()
m = re.search(r"\[bench\] (\d+) spheres; time step ([0-9.eE+-]+) s", t)
if not m: sys.exit("cannot find '[bench] N spheres; time step DT s' in " + sys.argv[1])
print(m.group(1), m.group(2))
PY
) || die "could not read the sphere count and time step from $first_log"
# LIGGGHTS gets the bound of grainscale's adaptive skin, 0.2 x the largest radius (the fixed skin grainscale used before; dem/adaptive_skin.hpp); with diameter 13.4 mm and spread 0.05 the largest
# radius is at most 1.05 x 6.7 mm (not printed by grainscale; read from the YAML)
read -r SKIN TSETTLE < <(python3 - "$YAML" <<'PY'
import re, sys
t = open(sys.argv[1]).read()
num = lambda k: float(re.search(r"^\s*" + k + r":\s*([0-9.eE+-]+)", t, re.M).group(1))
d, s = num("diameter"), num("diameter_spread")
print(f"{0.2 * 0.5 * d * (1 + s):.6g}", num("end"))
PY
) || die "could not read diameter / time.end from $YAML"
say "problem: $GS_N spheres, dt = $GS_DT s, skin = $SKIN m, settle $TSETTLE s, $STEPS timed steps"

# ---------------------------------------------------------------- 3. LIGGGHTS: settle + timed
for n in $COUNTS; do
  if (( n > 1 )) && (( ${#MPIRUN[@]} == 0 )); then say "skipping LIGGGHTS with $n processes (no MPI)"; continue; fi
  launcher=()
  if (( ${#MPIRUN[@]} > 0 )); then
    launcher=("${MPIRUN[@]}" -np "$n")
    if (( n > NCPU )); then launcher+=(--oversubscribe); fi
  fi
  for r in $(seq 1 "$REPEATS"); do
    wait_idle
    log="$OUT/liggghts_np${n}_r${r}.log"
    say "LIGGGHTS, $n process(es), repeat $r: settle + $STEPS timed steps -> $log"
    (cd "$OUT" && run_logged "$log" "${launcher[@]}" "$LIGGGHTS" -in "$LIG_IN" -log none -echo none \
        -var n "$GS_N" -var dt "$GS_DT" -var skin "$SKIN" -var tsettle "$TSETTLE" \
        -var nsteps "$STEPS" -var px "$n") || die "LIGGGHTS failed (exit $?); see $log"
    grep -E '^Loop time' "$log" | tail -1 >&2 || die "no 'Loop time' line in $log"
  done
done

# ---------------------------------------------------------------- 4. table
machine_description | tee "$OUT/results.txt"
python3 - "$OUT" "$STEPS" "$REPEATS" "$COUNTS" "$GS_N" "$GS_DT" "$SKIN" "$TSETTLE" <<'PY' | tee -a "$OUT/results.txt"
import glob, os, re, sys
out, steps, repeats, counts = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), [int(c) for c in sys.argv[4].split()]
gs_n, gs_dt, skin, tsettle = sys.argv[5:9]

def load(log):
    try:
        return dict(zip(*[iter(open(log + ".load").read().split())] * 2))
    except OSError:
        return {}

def gs_rate(n):
    best = None
    for r in range(1, repeats + 1):
        log = f"{out}/grainscale_t{n}_r{r}.log"
        if not os.path.exists(log): continue
        m = re.search(r"^threads %d: (\d+) steps in ([0-9.]+) s = ([0-9.]+) M sphere-steps/s" % n, open(log).read(), re.M)
        if m and (best is None or float(m.group(3)) > best[0]):
            best = (float(m.group(3)), float(m.group(2)), log)
    return best

def lg_rate(n):
    best = None
    for r in range(1, repeats + 1):
        log = f"{out}/liggghts_np{n}_r{r}.log"
        if not os.path.exists(log): continue
        loops = re.findall(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", open(log).read(), re.M)
        if len(loops) < 2: continue
        t, p, ns, na = loops[-1]          # the last run is the timed one
        rate = int(ns) * int(na) / float(t) / 1e6
        if best is None or rate > best[0]:
            best = (rate, float(t), log)
    return best

print(f"box settle benchmark: {gs_n} spheres, dt = {gs_dt} s, skin = {skin} m, settled {tsettle} s, "
      f"{steps} timed steps (best of {repeats})")
print(f"{'threads/procs':>13} | {'grainscale':>10} | {'LIGGGHTS':>10} | {'ratio':>6} | {'gs s':>7} | {'lg s':>7} | other load (cores) gs / lg")
print(f"{'':>13} | {'M sph-st/s':>10} | {'M sph-st/s':>10} | {'gs/lg':>6} |")
for n in counts:
    g, l = gs_rate(n), lg_rate(n)
    gs_s = f"{g[0]:10.3f}" if g else f"{'n/a':>10}"
    lg_s = f"{l[0]:10.3f}" if l else f"{'n/a':>10}"
    ratio = f"{g[0] / l[0]:6.2f}" if g and l else f"{'n/a':>6}"
    gl = load(g[2]).get("other_cores", "?") if g else "-"
    ll = load(l[2]).get("other_cores", "?") if l else "-"
    print(f"{n:>13} | {gs_s} | {lg_s} | {ratio} | {g[1] if g else 0:7.2f} | {l[1] if l else 0:7.2f} | {gl} / {ll}")
print("(other load: CPU cores used by other processes during the run, wall-averaged; > 0.2 means the figure is disturbed)")
print()
print("every timed run (raw):")
for log in sorted(glob.glob(f"{out}/grainscale_t*_r*.log")):
    m = re.search(r"^threads (\d+): (\d+) steps in ([0-9.]+) s = ([0-9.]+) M sphere-steps/s", open(log).read(), re.M)
    if m:
        print(f"  grainscale {m.group(1)} thread(s): {m.group(2)} steps in {m.group(3)} s = {m.group(4)} M sphere-steps/s"
              f"   [{os.path.basename(log)}; other load {load(log).get('other_cores', '?')} cores, core round trip {load(log).get('core_round_trip_ns', '?')} ns]")
for log in sorted(glob.glob(f"{out}/liggghts_np*_r*.log")):
    loops = re.findall(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", open(log).read(), re.M)
    if len(loops) >= 2:
        t, p, ns, na = loops[-1]
        print(f"  LIGGGHTS {p} process(es): {ns} steps x {na} atoms in {t} s = {int(ns) * int(na) / float(t) / 1e6:.3f} M sphere-steps/s"
              f"   [{os.path.basename(log)}; other load {load(log).get('other_cores', '?')} cores, core round trip {load(log).get('core_round_trip_ns', '?')} ns]")

# settled-state check
print()
print("settled state (after the settling time, before the timed steps; z = sphere centres above the floor):")
rows = []
summ = f"{out}/grainscale_settled/summary.yaml"
gs = {}
if os.path.exists(summ):
    for line in open(summ):
        if ":" in line and not line.startswith("#"):
            k, v = line.split(":", 1); gs[k.strip()] = v.strip().strip('"')
glog = f"{out}/grainscale_t{counts[0]}_r1.log"
if os.path.exists(glog):
    m = re.search(r"^problem: .*?, (\d+) spheres, .*?, (\d+) contacts, (\d+) wall contacts", open(glog).read(), re.M)
    if m:
        gs.setdefault("particles", m.group(1)); gs["contacts"] = m.group(2); gs["wall_contacts"] = m.group(3)
for n in counts:
    log = f"{out}/liggghts_np{n}_r1.log"
    if not os.path.exists(log): continue
    m = re.search(r"^SETTLED atoms (\d+) mass_kg (\S+) ekin_J (\S+) zmax_m (\S+) zmean_m (\S+) contacts (\S+)", open(log).read(), re.M)
    if m:
        rows.append((f"LIGGGHTS np {n}", m.group(1), f"{float(m.group(2)):.4f}", f"{float(m.group(3)):.3g}", m.group(6).split('.')[0],
                     f"{1000 * float(m.group(4)):.1f}", f"{1000 * float(m.group(5)):.1f}"))
print(f"{'':>16} {'spheres':>8} {'mass kg':>8} {'KE J':>9} {'contacts':>8} {'z max mm':>9} {'z mean mm':>9}")
bed = {}
try:
    w = open(f"{out}/grainscale_settled/bed.txt").read().split(); bed = dict(zip(w[0::2], w[1::2]))
except (OSError, IndexError):
    pass
mm = lambda k: f"{1000 * float(bed[k]):.1f}" if k in bed else "n/a"
print(f"{'grainscale':>16} {gs.get('particles', '?'):>8} {'~3.5':>8} {float(gs['kinetic_energy_J']) if 'kinetic_energy_J' in gs else float('nan'):9.3g} "
      f"{gs.get('contacts', '?'):>8} {mm('zmax_m'):>9} {mm('zmean_m'):>9}   (+{gs.get('wall_contacts', '?')} wall contacts)")
for r in rows:
    print(f"{r[0]:>16} {r[1]:>8} {r[2]:>8} {r[3]:>9} {r[4]:>8} {r[5]:>9} {r[6]:>9}")
PY
say "logs and results.txt in $OUT"
