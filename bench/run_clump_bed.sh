#!/usr/bin/env bash
# "Clump bed" benchmark (issue 11): grainscale vs LIGGGHTS 3.8 (Debian package) on 2000 wheat-like
# 7-sphere clumps settled in a 5-wall box, side by side. See bench/README.md. Usage (from anywhere):
#   bench/run_clump_bed.sh
# Environment knobs (all optional):
#   STEPS=20000        timed steps after settling
#   COUNTS="1 2"       grainscale OpenMP threads / LIGGGHTS MPI processes to time
#   REPEATS=2          timed runs per code and count; the fastest is reported
#   SETTLE=            s simulated settling (default: time.end of bench/clump_bed.yaml, 0.6 s)
#   CLUMPS=2000        clumps (keep 2000 for the benchmark; smaller for a quick check of the script)
#   IDLE_WAIT=600      seconds to wait, before each timed run, for the machine to be idle (0: don't)
#   IDLE_MAX=10        % of all CPUs that other processes may use and still count as idle
#   BUILD_DIR=build    grainscale build folder (built if missing); GRAINSCALE=path overrides
#   OUT=bench/out/clump_bed   logs, settled states, results.txt
# Both codes settle once (untimed): grainscale into a checkpoint (`bench --settled`), LIGGGHTS into a
# restart file; every timed run starts from that state.
# Skins: grainscale runs as its users run it, with the adaptive skin (dem/adaptive_skin.hpp), and with
# the fixed skin LIGGGHTS users set (0.2 x the largest radius); LIGGGHTS runs with that fixed skin and
# (THIN=1, the default) with the skin grainscale's adaptive run ended with, so that every ratio has a
# like-for-like twin. Quick end-to-end check of the script:
#   STEPS=200 SETTLE=0.02 REPEATS=1 IDLE_WAIT=0 bench/run_clump_bed.sh
set -euo pipefail
BENCH_NAME=clump_bed
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/lib_bench.sh"

YAML="$HERE/clump_bed.yaml"
LIG_IN="$HERE/liggghts/in.clump_bed"
OUT="${OUT:-$HERE/out/clump_bed}"
STEPS="${STEPS:-20000}"
COUNTS="${COUNTS:-1 2}"
REPEATS="${REPEATS:-2}"
CLUMPS="${CLUMPS:-2000}"
[[ -f "$YAML" ]] || die "missing $YAML"
[[ -f "$LIG_IN" ]] || die "missing $LIG_IN"
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"

# the problem, read from the scenario: settle time, box floor, shape file and scale, density
read -r YAML_END SCALE SHAPE LX LY RHO < <(python3 - "$YAML" "$ROOT/studies/materials/report_table1.yaml" <<'PY'
import os, re, sys
t = open(sys.argv[1]).read()
code = "\n".join(l.split("#")[0] for l in t.split("\n"))
end = re.search(r"^\s*end:\s*([0-9.eE+-]+)", code, re.M).group(1)
scale = re.search(r"^scale_factor:\s*([0-9.eE+-]+)", code, re.M).group(1)
shape = re.search(r"shape:\s*(\S+)", code).group(1)
shape = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(sys.argv[1])), shape))
box = re.search(r"type:\s*box,\s*min:\s*\[([^\]]*)\],\s*max:\s*\[([^\]]*)\]", code)
lo, hi = [float(v) for v in box.group(1).split(",")], [float(v) for v in box.group(2).split(",")]
mat = open(sys.argv[2]).read()
rho = re.search(r"barley:\s*\{density:\s*([0-9.eE+-]+)", mat).group(1)
print(end, scale, shape, hi[0] - lo[0], hi[1] - lo[1], rho)
PY
) || die "could not read end / scale_factor / shape / box from $YAML"
SETTLE="${SETTLE:-$YAML_END}"
AREA="$(python3 -c "print($LX * $LY)")"

need_grainscale
need_liggghts

THIN="${THIN:-1}"
rm -f "$OUT"/grainscale_t*_r*.log* "$OUT"/grainscale_fixedskin_t*_r*.log* "$OUT"/liggghts_np*_r*.log* \
  "$OUT"/liggghts_thinskin_np*_r*.log* "$OUT/results.txt"

# ---------------------------------------------------------------- 1. grainscale: settle once
SCEN="$OUT/clump_bed.yaml"
yaml_with "$YAML" "$SCEN" "end=$SETTLE" "count=$CLUMPS"
CKPT="$OUT/grainscale_settled.h5"
rm -f "$CKPT"
say "grainscale: $CLUMPS clumps, settling $SETTLE s (untimed) -> $CKPT"
run_logged "$OUT/grainscale_settle.log" "$GS" bench "$SCEN" --steps 1 --threads 1 --settled "$CKPT" \
  || die "grainscale settle failed; see $OUT/grainscale_settle.log"
python3 "$HERE/h5_state.py" "$CKPT" --area "$AREA" --density "$RHO" >"$OUT/grainscale_settled.txt" \
  || die "could not read $CKPT"
read -r GS_N GS_B GS_DT GS_RMAX < <(python3 - "$OUT/grainscale_settled.txt" <<'PY'
import sys
w = open(sys.argv[1]).read().split(); s = dict(zip(w[0::2], w[1::2]))
print(s["spheres"], s["bodies"], s["dt_s"], s["rmax_m"])
PY
)
GS_SKIN="$(python3 -c "print(f'{0.2 * $GS_RMAX:.6g}')")"  # the fixed skin: 0.2 x the largest radius
SCEN_FIXED="$OUT/clump_bed_fixed_skin.yaml"
yaml_with "$YAML" "$SCEN_FIXED" "end=$SETTLE" "count=$CLUMPS" "skin=$GS_SKIN"
(( GS_B == CLUMPS )) || die "grainscale inserted $GS_B clumps, not $CLUMPS"
NPER=$(( GS_N / GS_B ))
say "problem: $GS_B clumps x $NPER spheres = $GS_N spheres, dt = $GS_DT s, fixed skin = $GS_SKIN m, settled $SETTLE s"

# ---------------------------------------------------------------- 2. LIGGGHTS: settle once
# the clump: grainscale's shape file (x y z r, in its length unit) scaled like grainscale scales it
read -r UNIT < <(python3 - "$SHAPE" "$OUT/wheat.multisphere" <<'PY'
import re, sys
t = open(sys.argv[1]).read()
code = "\n".join(l.split("#")[0] for l in t.split("\n"))
m = re.search(r"^length_unit:\s*(\S+)", code, re.M)
unit = {"mm": 0.001, "m": 1.0}[m.group(1) if m else "m"]
rows = [(m.group(1), m.group(2)) for m in re.finditer(r"center:\s*\[([^\]]*)\],\s*radius:\s*([0-9.eE+-]+)", code)]
with open(sys.argv[2], "w") as f:
    for c, r in rows:
        f.write(" ".join(v.strip() for v in c.split(",")) + " " + r + "\n")
print(unit)
PY
) || die "could not write the LIGGGHTS sphere file from $SHAPE"
SHAPESCALE="$(python3 -c "print($UNIT * $SCALE)")"
LIG_VARS=(-var shape "$OUT/wheat.multisphere" -var shapescale "$SHAPESCALE" -var nper "$NPER" -var n "$GS_B"
          -var dt "$GS_DT" -var tsettle "$SETTLE" -var nsteps "$STEPS"
          -var lx "$LX" -var ly "$LY" -var restart "$OUT/liggghts_settled.restart")
say "LIGGGHTS: $GS_B clumps, settling $SETTLE s (untimed, 1 process) -> $OUT/liggghts_settled.restart"
rm -f "$OUT/liggghts_settled.restart"
(cd "$OUT" && run_logged "$OUT/liggghts_settle.log" "$LIGGGHTS" -in "$LIG_IN" -log none -echo none \
    "${LIG_VARS[@]}" -var skin "$GS_SKIN" -var mode 1 -var px 1) || die "LIGGGHTS settle failed; see $OUT/liggghts_settle.log"
grep -E '^SETTLED' "$OUT/liggghts_settle.log" >&2 || die "no SETTLED line in $OUT/liggghts_settle.log"
# ---------------------------------------------------------------- 3. both codes timed, run by run
# Interleaved: in each repeat, for each count, grainscale (adaptive, then fixed skin) and right after
# it LIGGGHTS (fixed, then thin skin). This VM's speed drifts by up to 2x within minutes; timed one code's
# runs after the other's, the two sides of a ratio would be minutes apart. So the runs of a ratio are
# seconds apart, and each repeat gives a paired ratio besides the best-of-the-repeats one.
GS_THIN=""
FIRST_COUNT="${COUNTS%% *}"
skins=(fixed); if [[ "$THIN" == 1 ]]; then skins+=(thin); fi
for r in $(seq 1 "$REPEATS"); do
  for n in $COUNTS; do
    # grainscale (from the same checkpoint: under the fixed-skin scenario the list is rebuilt with
    # that skin at the first warm-up step)
    for variant in adaptive fixed; do
      wait_idle
      if [[ $variant == adaptive ]]; then log="$OUT/grainscale_t${n}_r${r}.log" scen="$SCEN"
      else log="$OUT/grainscale_fixedskin_t${n}_r${r}.log" scen="$SCEN_FIXED"; fi
      say "grainscale bench, $variant skin, $n thread(s), repeat $r: $STEPS timed steps from the settled state -> $log"
      run_logged "$log" "$GS" bench "$scen" --steps "$STEPS" --threads "$n" --settled "$CKPT" \
        || die "grainscale bench failed (exit $?); see $log"
      grep -E '^threads' "$log" >&2 || die "no 'threads N:' line in $log"
    done
    if [[ -z "$GS_THIN" ]]; then
      # the skin grainscale's adaptive runs end with (the same for every count: the state is bit for bit)
      GS_THIN="$(sed -nE 's/^threads [0-9]+: neighbour list at the end: skin ([0-9.eE+-]+) m.*/\1/p' "$OUT/grainscale_t${FIRST_COUNT}_r1.log" | head -1)"
      [[ -n "$GS_THIN" ]] || die "no 'neighbour list at the end' line in $OUT/grainscale_t${FIRST_COUNT}_r1.log"
      say "grainscale's adaptive skin at the end of its timed steps: $GS_THIN m (fixed: $GS_SKIN m)"
    fi
    # LIGGGHTS
    launcher=()
    if (( n > 1 )); then
      if (( ${#MPIRUN[@]} == 0 )); then say "skipping LIGGGHTS with $n processes (no MPI)"; continue; fi
      launcher=("${MPIRUN[@]}" -np "$n")
      if (( n > NCPU )); then launcher+=(--oversubscribe); fi
    fi
    for variant in "${skins[@]}"; do
      wait_idle
      if [[ $variant == fixed ]]; then log="$OUT/liggghts_np${n}_r${r}.log" skin="$GS_SKIN"
      else log="$OUT/liggghts_thinskin_np${n}_r${r}.log" skin="$GS_THIN"; fi
      say "LIGGGHTS, skin $skin m, $n process(es), repeat $r: $STEPS timed steps from the settled state -> $log"
      (cd "$OUT" && run_logged "$log" "${launcher[@]}" "$LIGGGHTS" -in "$LIG_IN" -log none -echo none \
          "${LIG_VARS[@]}" -var skin "$skin" -var mode 2 -var px "$n") || die "LIGGGHTS failed (exit $?); see $log"
      grep -E '^Loop time' "$log" | tail -1 >&2 || die "no 'Loop time' line in $log"
    done
  done
done

# ---------------------------------------------------------------- 4. table
machine_description | tee "$OUT/results.txt"
python3 - "$OUT" "$STEPS" "$REPEATS" "$COUNTS" "$GS_N" "$GS_B" "$GS_DT" "$GS_SKIN" "$SETTLE" "$AREA" "$RHO" "$GS_THIN" \
  <<'PY' | tee -a "$OUT/results.txt"
import glob, os, re, sys
out, steps, repeats = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
counts = [int(c) for c in sys.argv[4].split()]
n_sph, n_body, dt, skin, settle, area, rho = int(sys.argv[5]), int(sys.argv[6]), sys.argv[7], sys.argv[8], sys.argv[9], float(sys.argv[10]), float(sys.argv[11])
thin = sys.argv[12]

def kv(path):
    try:
        w = open(path).read().split(); return dict(zip(w[0::2], w[1::2]))
    except OSError:
        return {}

def load(log):
    return kv(log + ".load")

def gs_run(log):
    t = open(log).read()
    m = re.search(r"^threads (\d+): (\d+) steps in ([0-9.]+) s = ([0-9.]+) M sphere-steps/s .*?, ([0-9.eE+-]+) contacts/s", t, re.M)
    mem = re.search(r"^memory: ([0-9.]+) bytes per sphere", t, re.M)
    if not m: return None
    return {"rate": float(m.group(4)) * 1e6, "s": float(m.group(3)), "cps": float(m.group(5)),
            "bytes": float(mem.group(1)) if mem else float("nan"), "log": log}

def lg_run(log):
    t = open(log).read()
    loops = re.findall(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", t, re.M)
    timed = re.search(r"^TIMED atoms (\d+) bodies (\S+) ekin_J (\S+) zmean_m (\S+) contacts (\S+)", t, re.M)
    mem = re.findall(r"^Memory usage per processor = ([0-9.eE+-]+) Mbytes", t, re.M)
    if not loops or not timed: return None
    s, p, ns, na = loops[-1]
    s, p, ns, na = float(s), int(p), int(ns), int(na)
    return {"rate": ns * na / s, "s": s, "cps": float(timed.group(5)) * ns / s,
            "bytes": float(mem[-1]) * 2**20 * p / na if mem else float("nan"), "log": log, "atoms": na}

def best(kind, n):
    runs = []
    for r in range(1, repeats + 1):
        log = f"{out}/{kind}_{'t' if kind.startswith('grainscale') else 'np'}{n}_r{r}.log"
        if os.path.exists(log):
            x = (gs_run if kind.startswith("grainscale") else lg_run)(log)
            if x: runs.append(x)
    return max(runs, key=lambda x: x["rate"]) if runs else None

M = lambda x: f"{x / 1e6:8.3f}"
print(f"clump bed benchmark: {n_body} clumps x {n_sph // n_body} spheres = {n_sph} spheres, dt = {dt} s, "
      f"settled {settle} s, {steps} timed steps (best of {repeats})")
print(f"skins: fixed = {skin} m (0.2 x the largest radius, what LIGGGHTS users set); adaptive = grainscale's default "
      f"(dem/adaptive_skin.hpp), which ended at {thin} m; thin = LIGGGHTS given that skin")
print("rates in millions per second of wall clock; per core = divided by the threads / processes")
rows = [("grainscale", "grainscale", "adaptive"), ("grainscale_fixedskin", "grainscale", "fixed"),
        ("liggghts", "LIGGGHTS", "fixed"), ("liggghts_thinskin", "LIGGGHTS", "thin")]
hdr = f"{'code':>10} {'skin':>8} {'n':>2} | {'sph-st/s':>8} {'per core':>8} {'clump-st':>8} {'contact/s':>9} | {'B/sphere':>8} {'RSS B/sph':>9} | {'s':>7} | other load"
print(hdr); print("-" * len(hdr))
res = {}
for n in counts:
    for kind, code, sk in rows:
        x = best(kind, n)
        res[kind, n] = x
        if not x:
            print(f"{code:>10} {sk:>8} {n:>2} | {'n/a':>8}"); continue
        ld = load(x["log"])
        rss = int(ld.get("maxrss_kb", 0)) * 1024 / n_sph
        print(f"{code:>10} {sk:>8} {n:>2} | {M(x['rate'])} {M(x['rate'] / n)} {M(x['rate'] * n_body / n_sph)} {M(x['cps']):>9} | "
              f"{x['bytes']:8.0f} {rss:9.0f} | {x['s']:7.2f} | {ld.get('other_cores', '?')}")
print()
pairs = [("grainscale", "liggghts", "each as its users run it (grainscale adaptive, LIGGGHTS fixed skin)"),
         ("grainscale_fixedskin", "liggghts", "both with the fixed skin"),
         ("grainscale", "liggghts_thinskin", "both with grainscale's adaptive skin")]
for a_kind, b_kind, what in pairs:
    for n in counts:
        g, l = res.get((a_kind, n)), res.get((b_kind, n))
        r = f"{g['rate'] / l['rate']:.2f}" if g and l else "n/a"
        print(f"ratio grainscale / LIGGGHTS per core at {n} thread(s) / process(es), {what}: {r}")
for kind, code, sk in rows:
    a, b = res.get((kind, counts[0])), res.get((kind, counts[-1]))
    if a and b and counts[-1] != counts[0]:
        print(f"{code} ({sk} skin) speed-up {counts[0]} -> {counts[-1]}: {b['rate'] / a['rate']:.2f}x")

# Paired: the runs of one repeat, seconds apart (the script interleaves the codes), so a drift of the
# VM's speed between repeats cancels; the median of the repeats' ratios.
def run_of(kind, n, r):
    log = f"{out}/{kind}_{'t' if kind.startswith('grainscale') else 'np'}{n}_r{r}.log"
    return (gs_run if kind.startswith("grainscale") else lg_run)(log) if os.path.exists(log) else None

def median(v):
    v = sorted(v); m = len(v) // 2
    return v[m] if len(v) % 2 else 0.5 * (v[m - 1] + v[m])

def paired(a_kind, a_n, b_kind, b_n):
    ratios = []
    for r in range(1, repeats + 1):
        a, b = run_of(a_kind, a_n, r), run_of(b_kind, b_n, r)
        if a and b: ratios.append(a["rate"] / b["rate"])
    return ratios

print()
print("paired by repeat (each repeat's two runs seconds apart; the median of the repeats):")
for a_kind, b_kind, what in pairs:
    for n in counts:
        v = paired(a_kind, n, b_kind, n)
        if v:
            print(f"  grainscale / LIGGGHTS per core at {n} thread(s) / process(es), {what}: "
                  f"{' '.join(f'{x:.2f}' for x in v)} -> median {median(v):.2f}")
for kind, code, sk in rows:
    if counts[-1] != counts[0]:
        v = paired(kind, counts[-1], kind, counts[0])
        if v:
            print(f"  {code} ({sk} skin) speed-up {counts[0]} -> {counts[-1]}: {' '.join(f'{x:.2f}' for x in v)} -> median {median(v):.2f}x")
print("(other load: CPU cores used by other processes during the run; > 0.2 means the figure is disturbed.")
print(" B/sphere: each code's own count (grainscale: arrays it holds; LIGGGHTS: 'Memory usage per processor' x")
print(" processes, its estimate). RSS B/sph: peak resident memory of the largest process / spheres, libraries")
print(" and MPI buffers included.)")
print()
print("every timed run (raw):")
for log in sorted(glob.glob(f"{out}/grainscale_*t*_r*.log")) + sorted(glob.glob(f"{out}/liggghts_*np*_r*.log")):
    x = (gs_run if "grainscale" in os.path.basename(log) else lg_run)(log)
    if x:
        print(f"  {os.path.basename(log):32} {x['rate'] / 1e6:8.3f} M sphere-steps/s in {x['s']:.2f} s   other load {load(log).get('other_cores', '?')} cores, core round trip {load(log).get('core_round_trip_ns', '?')} ns")
print("end of the timed steps (the same state for every count of a code: a run that disagrees misbehaved):")
for log in sorted(glob.glob(f"{out}/grainscale_*t*_r*.log")):
    t = open(log).read()
    m = re.search(r"end state: kinetic energy (\S+) J, (\d+) contacts, fingerprint (\w+)", t)
    e = re.search(r"neighbour list at the end: skin (\S+) m, (\S+) entries per sphere", t)
    if m:
        print(f"  {os.path.basename(log):32} KE {float(m.group(1)):.4g} J, {m.group(2)} contacts, fingerprint {m.group(3)} (bit for bit)"
              + (f"; skin {e.group(1)} m, {e.group(2)} list entries per sphere" if e else ""))
for log in sorted(glob.glob(f"{out}/liggghts_*np*_r*.log")):
    m = re.search(r"^TIMED atoms (\d+) bodies (\S+) ekin_J (\S+) zmean_m (\S+) contacts (\S+)", open(log).read(), re.M)
    if m:
        print(f"  {os.path.basename(log):32} KE {float(m.group(3)):.4g} J, mean centre height {1000 * float(m.group(4)):.2f} mm, "
              f"{int(float(m.group(5)))} contacts")

print()
print("settled state (before the timed steps): height = 2 x mean clump-centre z, phi = (mass / density) / (floor x height)")
g = kv(f"{out}/grainscale_settled.txt")
gt = open(f"{out}/grainscale_settle.log").read() if os.path.exists(f"{out}/grainscale_settle.log") else ""
m = re.search(r"^problem: .*?, (\d+) contacts, (\d+) wall contacts", gt, re.M)
g_contacts = m.group(1) if m else "?"
lt = open(f"{out}/liggghts_settle.log").read() if os.path.exists(f"{out}/liggghts_settle.log") else ""
s = re.search(r"^SETTLED atoms (\d+) bodies (\S+) ekin_J (\S+) zmax_m (\S+) zmean_m (\S+) contacts (\S+)", lt, re.M)
ins = re.search(r"inserted (\d+) particle templates \(mass ([0-9.eE+-]+)\)", lt)
print(f"{'':>10} {'spheres':>7} {'clumps':>6} {'mass kg':>8} {'KE J':>9} {'contacts':>8} {'zmax mm':>8} {'zmean mm':>8} {'height mm':>9} {'phi':>6}")
if g:
    print(f"{'grainscale':>10} {g['spheres']:>7} {g['bodies']:>6} {float(g['mass_kg']):8.4f} {float(g['ekin_J']):9.3g} {g_contacts:>8} "
          f"{1000 * float(g['zmax_m']):8.1f} {1000 * float(g['zmean_m']):8.1f} {1000 * float(g.get('height_m', 'nan')):9.1f} {g.get('phi', 'n/a'):>6}")
if s:
    mass = float(ins.group(2)) if ins else float("nan")
    zmean = float(s.group(5)); h = 2 * zmean
    phi = mass / rho / (area * h)
    print(f"{'LIGGGHTS':>10} {s.group(1):>7} {int(float(s.group(2))):>6} {mass:8.4f} {float(s.group(3)):9.3g} {int(float(s.group(6))):>8} "
          f"{1000 * float(s.group(4)):8.1f} {1000 * zmean:8.1f} {1000 * h:9.1f} {phi:6.4f}")
    if g:
        gm = float(g["mass_kg"])
        print(f"mass: LIGGGHTS / grainscale = {mass / gm:.5f} (grainscale: exact union volume of the 7 spheres x density; "
              f"LIGGGHTS: Monte Carlo estimate of the union, fix particletemplate/multisphere ntry 1e6)")
PY
say "logs and results.txt in $OUT"
