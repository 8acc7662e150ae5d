#!/usr/bin/env bash
# "Clump bed" benchmark (issue 11), LAMMPS side: the bed of run_clump_bed.sh (2000 wheat-like 7-sphere
# clumps settled in a 5-wall box) in LAMMPS (Debian package, GRANULAR + RIGID), timed the same way.
# See bench/README.md, "LAMMPS (clump bed)". Usage (from anywhere):
#   bench/run_clump_bed_lammps.sh
# Environment knobs (all optional), as run_clump_bed.sh:
#   STEPS=20000        timed steps after settling
#   COUNTS="1 2"       LAMMPS MPI processes to time
#   REPEATS=2          timed runs per count; the fastest is reported
#   SETTLE=            s simulated settling (default: time.end of bench/clump_bed.yaml, 0.6 s)
#   CLUMPS=2000        clumps (keep 2000 for the benchmark; smaller for a quick check of the script)
#   IDLE_WAIT=600      seconds to wait, before each timed run, for the machine to be idle (0: don't)
#   IDLE_MAX=10        % of all CPUs that other processes may use and still count as idle
#   OUT=bench/out/clump_bed_lammps   logs, settled state, results.txt
#   DT=, SKIN=         override the time step / skin (default: grainscale's rules, see below)
#   OTHER_OUT=bench/out/clump_bed    where run_clump_bed.sh left grainscale's and LIGGGHTS' settled
#                      beds; printed beside LAMMPS' when they have the same clump count
# LAMMPS settles once (untimed, 1 process) into a restart file (+ .rigid, the bodies' state); every
# timed run starts from it. Quick end-to-end check of the script:
#   STEPS=200 SETTLE=0.02 CLUMPS=200 REPEATS=1 IDLE_WAIT=0 bench/run_clump_bed_lammps.sh
set -euo pipefail
BENCH_NAME=clump_bed_lammps
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/lib_bench.sh"

YAML="$HERE/clump_bed.yaml"
LMP_IN="$HERE/lammps/in.clump_bed"
TOOL="$HERE/lammps/clump_bodies.py"
MATERIALS="$ROOT/studies/materials/report_table1.yaml"
OUT="${OUT:-$HERE/out/clump_bed_lammps}"
OTHER_OUT="${OTHER_OUT:-$HERE/out/clump_bed}"
STEPS="${STEPS:-20000}"
COUNTS="${COUNTS:-1 2}"
REPEATS="${REPEATS:-2}"
CLUMPS="${CLUMPS:-2000}"
for f in "$YAML" "$LMP_IN" "$TOOL" "$MATERIALS"; do [[ -f "$f" ]] || die "missing $f"; done
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"

# LAMMPS from Debian, installed if missing; it must have the GRANULAR, RIGID and MOLECULE packages.
# Sets LMP, LMP_VERSION and MPIRUN=(mpirun [--allow-run-as-root]) when it is MPI-built.
need_lammps() {
  find_lammps() {
    local c
    for c in lmp lmp_serial lmp_mpi; do
      if command -v "$c" >/dev/null 2>&1; then command -v "$c"; return 0; fi
    done
    return 1
  }
  if ! LMP="$(find_lammps)"; then
    say "LAMMPS not found; installing the Debian package 'lammps'"
    apt_install lammps
    LMP="$(find_lammps)" || die "lammps installed but no lmp executable on PATH"
  fi
  local help pk
  help="$("$LMP" -h 2>&1 </dev/null)" || true
  for pk in GRANULAR RIGID MOLECULE; do
    # the package list: the lines between "Installed packages:" and "List of individual style options"
    [[ $(awk '/^Installed packages:/{f=1; next} /^List of individual/{f=0} f' <<<"$help" | grep -c -w "$pk") -gt 0 ]] \
      || die "$LMP lacks the $pk package (see '$LMP -h')"
  done
  LMP_VERSION="$(sed -n '2p' <<<"$help" | sed 's/^Large-scale Atomic\/Molecular Massively Parallel Simulator - //')"
  say "LAMMPS: $LMP ($LMP_VERSION; Debian $(dpkg-query -W -f='${Version}' lammps 2>/dev/null || echo '?'))"
  MPIRUN=()
  if [[ $(ldd "$LMP" 2>/dev/null | grep -c libmpi) -gt 0 ]]; then
    if command -v mpirun >/dev/null 2>&1; then
      MPIRUN=(mpirun)
      if mpirun --version 2>&1 | grep -c 'Open MPI' >/dev/null && [[ "$(id -u)" -eq 0 ]]; then
        MPIRUN+=(--allow-run-as-root)
      fi
    else
      say "warning: lmp is MPI-built but mpirun is missing; only 1 process will be run"
    fi
  else
    say "warning: lmp is not MPI-built; only 1 process will be run"
  fi
}

# the problem, read from the scenario as run_clump_bed.sh reads it: settle time, box floor, shape file
# and scale, the particles' material (density, G, nu), grainscale's time-step fraction and skin
read -r YAML_END SCALE SHAPE LX LY RHO G NU FRAC SKIN_YAML < <(python3 - "$YAML" "$MATERIALS" <<'PY'
import os, re, sys
t = open(sys.argv[1]).read()
code = "\n".join(l.split("#")[0] for l in t.split("\n"))
end = re.search(r"^\s*end:\s*([0-9.eE+-]+)", code, re.M).group(1)
scale = re.search(r"^scale_factor:\s*([0-9.eE+-]+)", code, re.M).group(1)
shape = re.search(r"shape:\s*(\S+)", code).group(1)
shape = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(sys.argv[1])), shape))
box = re.search(r"type:\s*box,\s*min:\s*\[([^\]]*)\],\s*max:\s*\[([^\]]*)\]", code)
lo, hi = [float(v) for v in box.group(1).split(",")], [float(v) for v in box.group(2).split(",")]
part = code.split("particles:", 1)[1]
mat = re.search(r"material:\s*(\w+)", part).group(1)
frac = re.search(r"^\s*step_fraction:\s*([0-9.eE+-]+)", code, re.M)
skin = re.search(r"^\s*skin:\s*([0-9.eE+-]+)", code, re.M)
m = open(sys.argv[2]).read()
props = re.search(mat + r":\s*\{([^}]*)\}", m).group(1)
get = lambda k: re.search(k + r":\s*([0-9.eE+-]+)", props).group(1)
print(end, scale, shape, hi[0] - lo[0], hi[1] - lo[1], get("density"), get("shear_modulus"), get("poisson_ratio"),
      frac.group(1) if frac else 0.2, skin.group(1) if skin else "auto")
PY
) || die "could not read end / scale_factor / shape / box / material from $YAML"
SETTLE="${SETTLE:-$YAML_END}"
AREA="$(python3 -c "print($LX * $LY)")"

need_lammps

rm -f "$OUT"/lammps_np*_r*.log* "$OUT"/lammps_np*_r*.dump "$OUT/results.txt"

# ---------------------------------------------------------------- 1. the clump
# grainscale's shape file scaled like run_clump_bed.sh scales it for LIGGGHTS (length unit x scale
# factor), as a molecule file with the union's exact mass properties
read -r UNIT < <(python3 - "$SHAPE" <<'PY'
import re, sys
t = open(sys.argv[1]).read()
code = "\n".join(l.split("#")[0] for l in t.split("\n"))
m = re.search(r"^length_unit:\s*(\S+)", code, re.M)
print({"mm": 0.001, "m": 1.0}[m.group(1) if m else "m"])
PY
) || die "could not read the length unit of $SHAPE"
SHAPESCALE="$(python3 -c "print($UNIT * $SCALE)")"
MOL="$OUT/wheat.mol"
CLUMP="$(python3 "$TOOL" molecule "$SHAPE" "$SHAPESCALE" "$RHO" "$MOL")" || die "could not write $MOL"
read -r MCLUMP RMIN RMAX < <(python3 -c "
w = '''$CLUMP'''.split(); s = dict(zip(w[0::2], w[1::2])); print(s['mass_kg'], s['rmin'], s['rmax'])")
NPER="$(grep -E '^[0-9]+ atoms' "$MOL" | awk '{print $1}')"
# grainscale's rules (dem/time_step.hpp, dem/simulation.cpp): dt = step_fraction x the Rayleigh time of
# the smallest sphere, skin = 0.2 x the largest radius
DT="${DT:-$(python3 -c "
import math
print(f'{$FRAC * math.pi * $RMIN * math.sqrt($RHO / $G) / (0.1631 * $NU + 0.8766):.6g}')")}"
if [[ -z "${SKIN:-}" ]]; then
  # (time.skin 0 is grainscale's adaptive skin: LAMMPS gets the fixed 0.2 x the largest radius its users set)
  if [[ "$SKIN_YAML" == auto ]] || python3 -c "import sys; sys.exit(float('$SKIN_YAML') != 0)"; then
    SKIN="$(python3 -c "print(f'{0.2 * $RMAX:.6g}')")"
  else
    SKIN="$SKIN_YAML"
  fi
fi
say "problem: $CLUMPS clumps x $NPER spheres, clump $CLUMP"
say "dt = $DT s, skin = $SKIN m, settle $SETTLE s, box $LX x $LY m"

RESTART="$OUT/lammps_settled.restart"
LMP_VARS=(-var mol "$MOL" -var tool "python3 $TOOL" -var mclump "$MCLUMP" -var rmax "$RMAX" -var n "$CLUMPS"
          -var dt "$DT" -var skin "$SKIN" -var tsettle "$SETTLE" -var nsteps "$STEPS"
          -var lx "$LX" -var ly "$LY" -var restart "$RESTART")

# ---------------------------------------------------------------- 2. settle once (untimed)
say "LAMMPS: $CLUMPS clumps, settling $SETTLE s (untimed, 1 process) -> $RESTART"
rm -f "$RESTART" "$RESTART".*
(cd "$OUT" && run_logged "$OUT/lammps_settle.log" "$LMP" -in "$LMP_IN" -log none -echo none -nocite \
    "${LMP_VARS[@]}" -var mode 1 -var px 1) || die "LAMMPS settle failed; see $OUT/lammps_settle.log"
grep -E '^SETTLED' "$OUT/lammps_settle.log" >&2 || die "no SETTLED line in $OUT/lammps_settle.log"
[[ -f "$RESTART.rigid" ]] || die "no $RESTART.rigid (the bodies' state) after the settle"

# the settled bed: clumps rigid (sphere distances as in the template), every sphere inside the box
python3 - "$TOOL" "$MOL" "$RESTART.dump" "$LX" "$LY" "$CLUMPS" >"$OUT/lammps_settled_check.txt" <<'PY' \
  || die "settled-state check failed; see $OUT/lammps_settled_check.txt"
import subprocess, sys
tool, mol, dump, lx, ly, n = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6])
rig = subprocess.run([sys.executable, tool, "check", mol, dump], capture_output=True, text=True, check=True).stdout.split()
r = dict(zip(rig[0::2], rig[1::2]))
lines = open(dump).read().split("\n")
i = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
cols = lines[i].split()[2:]
rows = [[float(v) for v in l.split()] for l in lines[i + 1:] if l.strip()]
x, y, z, rad = (cols.index(c) for c in ("x", "y", "z", "radius"))
# how far a sphere reaches past each wall (> 0: into it; a Hertz overlap is a few micrometres)
past = max(max(-(a[x] - a[rad]), a[x] + a[rad] - lx, -(a[y] - a[rad]), a[y] + a[rad] - ly, -(a[z] - a[rad])) for a in rows)
lowest = min(a[z] - a[rad] for a in rows)
ok = int(r["clumps"]) == n and float(r["max_distance_error_m"]) < 1e-9 and past < 1e-4
print(f"clumps {r['clumps']} max_distance_error_m {r['max_distance_error_m']} max_wall_overlap_m {past:.3g} "
      f"lowest_sphere_bottom_m {lowest:.3g} ok {int(ok)}")
sys.exit(0 if ok else 1)
PY
say "settled bed: $(cat "$OUT/lammps_settled_check.txt")"

# ---------------------------------------------------------------- 3. timed runs
for n in $COUNTS; do
  launcher=()
  if (( n > 1 )); then
    if (( ${#MPIRUN[@]} == 0 )); then say "skipping LAMMPS with $n processes (no MPI)"; continue; fi
    launcher=("${MPIRUN[@]}" -np "$n")
    if (( n > NCPU )); then launcher+=(--oversubscribe); fi
  fi
  for r in $(seq 1 "$REPEATS"); do
    wait_idle
    log="$OUT/lammps_np${n}_r${r}.log"
    say "LAMMPS, $n process(es), repeat $r: $STEPS timed steps from the settled state -> $log"
    (cd "$OUT" && run_logged "$log" "${launcher[@]}" "$LMP" -in "$LMP_IN" -log none -echo none -nocite \
        "${LMP_VARS[@]}" -var mode 2 -var px "$n" -var enddump "$OUT/lammps_np${n}_r${r}.dump") \
      || die "LAMMPS failed (exit $?); see $log"
    grep -E '^Loop time' "$log" | tail -1 >&2 || die "no 'Loop time' line in $log"
    python3 "$TOOL" check "$MOL" "$OUT/lammps_np${n}_r${r}.dump" >"$log.rigid" || die "rigidity check failed"
  done
done

# ---------------------------------------------------------------- 4. table
machine_description | tee "$OUT/results.txt"
python3 - "$OUT" "$STEPS" "$REPEATS" "$COUNTS" "$CLUMPS" "$NPER" "$DT" "$SKIN" "$SETTLE" "$AREA" "$RHO" \
  "$LMP_VERSION" "$OTHER_OUT" <<'PY' | tee -a "$OUT/results.txt"
import glob, os, re, sys
out, steps, repeats = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
counts = [int(c) for c in sys.argv[4].split()]
n_body, nper, dt, skin, settle = int(sys.argv[5]), int(sys.argv[6]), sys.argv[7], sys.argv[8], sys.argv[9]
area, rho, version, other = float(sys.argv[10]), float(sys.argv[11]), sys.argv[12], sys.argv[13]
n_sph = n_body * nper

def kv(path):
    try:
        w = open(path).read().split(); return dict(zip(w[0::2], w[1::2]))
    except OSError:
        return {}

def run(log):
    t = open(log).read()
    loops = re.findall(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", t, re.M)
    timed = re.search(r"^TIMED atoms (\d+) bodies (\S+) ekin_J (\S+) zmean_m (\S+) contacts (\S+)", t, re.M)
    mem = re.findall(r"^Per MPI rank memory allocation \(min/avg/max\) = \S+ \| ([0-9.eE+-]+) \| \S+ Mbytes", t, re.M)
    neigh = re.findall(r"^Total # of neighbors = (\d+)", t, re.M)
    if not loops or not timed: return None
    s, p, ns, na = loops[-1]
    s, p, ns, na = float(s), int(p), int(ns), int(na)
    return {"rate": ns * na / s, "s": s, "p": p, "cps": float(timed.group(5)) * ns / s,
            "contacts": float(timed.group(5)), "ke": float(timed.group(3)), "zmean": float(timed.group(4)),
            "bytes": float(mem[-1]) * 2**20 * p / na if mem else float("nan"),
            "neigh": int(neigh[-1]) if neigh else None, "log": log, "atoms": na}

def best(n):
    runs = [x for x in (run(f) for f in sorted(glob.glob(f"{out}/lammps_np{n}_r*.log"))
                        if re.search(rf"_r\d+\.log$", f)) if x]
    return max(runs, key=lambda x: x["rate"]) if runs else None

M = lambda x: f"{x / 1e6:8.3f}"
print(f"clump bed benchmark, LAMMPS ({version}): {n_body} clumps x {nper} spheres = {n_sph} spheres, "
      f"dt = {dt} s, skin = {skin} m, settled {settle} s, {steps} timed steps (best of {repeats})")
print("rates in millions per second of wall clock; per core = divided by the MPI processes")
hdr = f"{'code':>10} {'n':>2} | {'sph-st/s':>8} {'per core':>8} {'clump-st':>8} {'contact/s':>9} | {'B/sphere':>8} {'RSS B/sph':>9} | {'s':>7} | other load"
print(hdr); print("-" * len(hdr))
res = {}
for n in counts:
    x = best(n); res[n] = x
    if not x:
        print(f"{'LAMMPS':>10} {n:>2} | {'n/a':>8}"); continue
    ld = kv(x["log"] + ".load")
    rss = int(ld.get("maxrss_kb", 0)) * 1024 / n_sph
    print(f"{'LAMMPS':>10} {n:>2} | {M(x['rate'])} {M(x['rate'] / n)} {M(x['rate'] * n_body / n_sph)} {M(x['cps']):>9} | "
          f"{x['bytes']:8.0f} {rss:9.0f} | {x['s']:7.2f} | {ld.get('other_cores', '?')}")
print()
a, b = res.get(counts[0]), res.get(counts[-1])
if a and b and counts[-1] != counts[0]:
    print(f"LAMMPS speed-up {counts[0]} -> {counts[-1]}: {b['rate'] / a['rate']:.2f}x")
print("(sph-st/s: steps x spheres / 'Loop time' of the timed run. contact/s: sphere-sphere contacts at the end")
print(" of the timed steps (compute contact/atom summed, halved: each contact is counted by both spheres;")
print(" wall contacts not included, as for LIGGGHTS) x steps / time. B/sphere: LAMMPS' 'Per MPI rank memory")
print(" allocation' average x processes / spheres, its estimate. RSS B/sph: peak resident memory of the largest")
print(" process / spheres. other load: CPU cores used by other processes during the run; > 0.2 is disturbed.)")
print()
print("every timed run (raw):")
for log in sorted(glob.glob(f"{out}/lammps_np*_r*.log")):
    if not re.search(r"_r\d+\.log$", log): continue
    x = run(log)
    if x:
        rig = kv(log + ".rigid")
        nb = f", {x['neigh']} pair neighbours ({x['neigh'] / x['atoms']:.2f} per sphere)" if x["neigh"] is not None else ""
        print(f"  {os.path.basename(log):22} {x['rate'] / 1e6:8.3f} M sphere-steps/s in {x['s']:.2f} s, other load "
              f"{kv(log + '.load').get('other_cores', '?')} cores; end: KE {x['ke']:.4g} J, mean centre height "
              f"{1000 * x['zmean']:.2f} mm, {int(x['contacts'])} contacts{nb}; clumps rigid to "
              f"{rig.get('max_distance_error_m', '?')} m")

print()
print("settled state (before the timed steps): height = 2 x mean clump-centre z, phi = (mass / density) / (floor x height)")
print(f"{'':>10} {'spheres':>7} {'clumps':>6} {'mass kg':>8} {'KE J':>9} {'contacts':>8} {'zmax mm':>8} {'zmean mm':>8} {'height mm':>9} {'phi':>6}")
lt = open(f"{out}/lammps_settle.log").read() if os.path.exists(f"{out}/lammps_settle.log") else ""
s = re.search(r"^SETTLED atoms (\d+) bodies (\S+) ekin_J (\S+) zmax_m (\S+) zmean_m (\S+) contacts (\S+) time_s (\S+) mass_kg (\S+)", lt, re.M)
if s:
    mass, zmean = float(s.group(8)), float(s.group(5)); h = 2 * zmean
    print(f"{'LAMMPS':>10} {s.group(1):>7} {int(float(s.group(2))):>6} {mass:8.4f} {float(s.group(3)):9.3g} {int(float(s.group(6))):>8} "
          f"{1000 * float(s.group(4)):8.1f} {1000 * zmean:8.1f} {1000 * h:9.1f} {mass / rho / (area * h):6.4f}")
# the other two codes' beds, as run_clump_bed.sh left them (its own random beds)
g = kv(f"{other}/grainscale_settled.txt")
if g and int(g.get("bodies", -1)) == n_body:
    gt = open(f"{other}/grainscale_settle.log").read() if os.path.exists(f"{other}/grainscale_settle.log") else ""
    m = re.search(r"^problem: .*?, (\d+) contacts, (\d+) wall contacts", gt, re.M)
    print(f"{'grainscale':>10} {g['spheres']:>7} {g['bodies']:>6} {float(g['mass_kg']):8.4f} {float(g['ekin_J']):9.3g} {m.group(1) if m else '?':>8} "
          f"{1000 * float(g['zmax_m']):8.1f} {1000 * float(g['zmean_m']):8.1f} {1000 * float(g.get('height_m', 'nan')):9.1f} {g.get('phi', 'n/a'):>6}")
lg = open(f"{other}/liggghts_settle.log").read() if os.path.exists(f"{other}/liggghts_settle.log") else ""
s2 = re.search(r"^SETTLED atoms (\d+) bodies (\S+) ekin_J (\S+) zmax_m (\S+) zmean_m (\S+) contacts (\S+)", lg, re.M)
ins = re.search(r"inserted (\d+) particle templates \(mass ([0-9.eE+-]+)\)", lg)
if s2 and int(float(s2.group(2))) == n_body:
    mass = float(ins.group(2)) if ins else float("nan")
    zmean = float(s2.group(5)); h = 2 * zmean
    print(f"{'LIGGGHTS':>10} {s2.group(1):>7} {int(float(s2.group(2))):>6} {mass:8.4f} {float(s2.group(3)):9.3g} {int(float(s2.group(6))):>8} "
          f"{1000 * float(s2.group(4)):8.1f} {1000 * zmean:8.1f} {1000 * h:9.1f} {mass / rho / (area * h):6.4f}")
if (g and int(g.get("bodies", -1)) == n_body) or (s2 and int(float(s2.group(2))) == n_body):
    print(f"(grainscale and LIGGGHTS rows: {other}, from run_clump_bed.sh; three different random beds)")
chk = kv(f"{out}/lammps_settled_check.txt")
if chk:
    print(f"LAMMPS settled bed: clumps rigid to {chk.get('max_distance_error_m')} m (sphere-sphere distances within a clump "
          f"against the template), deepest wall overlap {chk.get('max_wall_overlap_m')} m, lowest sphere bottom "
          f"{chk.get('lowest_sphere_bottom_m')} m")
PY
say "logs and results.txt in $OUT"
