# Shared helpers of the benchmark scripts (sourced, not run): run_box_settle.sh, run_clump_bed.sh,
# run_scaling.sh, run_platform_rate.sh.
# Before sourcing, set BENCH_NAME (message prefix). Provides:
#   HERE ROOT NCPU HZ; die say; need_grainscale (sets GS); need_liggghts (sets LIGGGHTS, MPIRUN);
#   busy_jiffies other_cpu_percent wait_idle (IDLE_WAIT, IDLE_MAX); core_round_trip; memory_latency;
#   run_logged LOG CMD...;
#   machine_description (first lines of every results.txt);
#   yaml_with FILE OUT KEY=VALUE... (a copy of a scenario with keys replaced, paths made absolute).

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/.." && pwd)"
IDLE_WAIT="${IDLE_WAIT:-600}"
IDLE_MAX="${IDLE_MAX:-10}"
NCPU="$(nproc)"
HZ="$(getconf CLK_TCK)"

die() { echo "${BENCH_NAME:-bench}: error: $*" >&2; exit 1; }
say() { echo "[${BENCH_NAME:-bench}] $*" >&2; }

command -v python3 >/dev/null || die "python3 is needed to read the logs"
[[ -x /usr/bin/time ]] || die "/usr/bin/time is needed (apt-get install time)"

# grainscale: BUILD_DIR (default build/) is configured and built (target grainscale) if the executable
# is missing; GRAINSCALE=/path/to/grainscale uses that executable instead.
need_grainscale() {
  local bd="${BUILD_DIR:-$ROOT/build}"
  [[ "$bd" = /* ]] || bd="$ROOT/$bd"
  GS="${GRAINSCALE:-$bd/studies/grainscale}"
  if [[ ! -x "$GS" ]]; then
    [[ -z "${GRAINSCALE:-}" ]] || die "GRAINSCALE=$GRAINSCALE is not an executable"
    say "grainscale not built; building into $bd (cmake -DCMAKE_BUILD_TYPE=Release, target grainscale)"
    (cd "$ROOT" && cmake -S . -B "$bd" -DCMAKE_BUILD_TYPE=Release && cmake --build "$bd" -j"$NCPU" --target grainscale) \
      || die "grainscale build failed"
  fi
  [[ -x "$GS" ]] || die "no executable at $GS"
  say "grainscale: $GS ($("$GS" version 2>/dev/null || echo 'version unknown'))"
}

# LIGGGHTS from Debian, installed if missing; MPIRUN=(mpirun [--allow-run-as-root]) when it is MPI-built
# Installs a Debian package (as root, or with sudo), or dies naming the command to run by hand.
apt_install() {
  local pkg="$1" sudo=""
  if [[ "$(id -u)" -ne 0 ]]; then
    command -v sudo >/dev/null || die "not root and no sudo: install it with 'apt-get install -y $pkg'"
    sudo="sudo"
  fi
  $sudo apt-get update -q || die "apt-get update failed"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q "$pkg" || die "apt-get install $pkg failed"
}

need_liggghts() {
  find_liggghts() {
    local c
    for c in liggghts lmp_debian liggghts-mpi; do
      if command -v "$c" >/dev/null 2>&1; then command -v "$c"; return 0; fi
    done
    return 1
  }
  if ! LIGGGHTS="$(find_liggghts)"; then
    say "LIGGGHTS not found; installing the Debian package 'liggghts'"
    apt_install liggghts
    LIGGGHTS="$(find_liggghts)" || die "liggghts installed but no liggghts executable on PATH"
  fi
  say "LIGGGHTS: $LIGGGHTS ($(dpkg-query -W -f='${Version}' liggghts 2>/dev/null || echo 'version unknown'))"
  MPIRUN=()
  # (grep -c, not grep -q: under pipefail an early-exiting grep kills ldd with SIGPIPE)
  if [[ $(ldd "$LIGGGHTS" 2>/dev/null | grep -c libmpi) -gt 0 ]]; then
    if command -v mpirun >/dev/null 2>&1; then
      MPIRUN=(mpirun)
      if mpirun --version 2>&1 | grep -c 'Open MPI' >/dev/null && [[ "$(id -u)" -eq 0 ]]; then
        MPIRUN+=(--allow-run-as-root)
      fi
    else
      say "warning: liggghts is MPI-built but mpirun is missing; only 1 process will be run"
    fi
  else
    say "warning: liggghts is not MPI-built; only 1 process will be run"
  fi
}

busy_jiffies() {  # busy and total jiffies of all CPUs
  awk '/^cpu /{b=$2+$3+$4+$7+$8+$9; print b, b+$5+$6}' /proc/stat
}

other_cpu_percent() {  # % of all CPUs busy over 2 s (call while none of ours is running)
  local a b
  a=($(busy_jiffies)); sleep 2; b=($(busy_jiffies))
  echo $(( 100 * (b[0] - a[0]) / (b[1] - a[1] > 0 ? b[1] - a[1] : 1) ))
}

# waits up to IDLE_WAIT s until other processes use at most IDLE_MAX % of the CPUs (IDLE_WAIT=0: never)
wait_idle() {
  local waited=0 p
  (( IDLE_WAIT > 0 )) || return 0
  while :; do
    p="$(other_cpu_percent)"
    if (( p <= IDLE_MAX )); then return 0; fi
    if (( waited >= IDLE_WAIT )); then
      say "warning: the machine is still ${p}% busy with other work after ${waited} s; timing anyway (figures will be low)"
      return 0
    fi
    if (( waited == 0 )); then say "waiting for other processes to finish (CPU ${p}% busy; up to ${IDLE_WAIT} s) ..."; fi
    sleep 8; waited=$(( waited + 10 ))
  done
}

# core_round_trip: ns a cache line takes from the first CPU to the second and back (bench/core_round_trip.c,
# compiled once into a temporary folder); "nan" with one CPU or no C compiler. On the VMs grainscale is
# measured on it moves between ~100 and ~480 ns within minutes, and a second thread's gain with it:
# every timed run records it.
core_round_trip() {
  if [[ -z "${CORE_RT_BIN:-}" ]]; then
    CORE_RT_BIN="$(mktemp -d)/core_round_trip"
    cc -O2 -pthread "$HERE/core_round_trip.c" -o "$CORE_RT_BIN" 2>/dev/null || CORE_RT_BIN=false
  fi
  if [[ "$CORE_RT_BIN" == false ]]; then echo nan; else "$CORE_RT_BIN" 2>/dev/null || echo nan; fi
}

# run_logged LOG CMD...: runs CMD with stdout+stderr to LOG; writes to LOG.load the wall time, own CPU,
# own peak resident memory (of the largest process), the CPU that other processes used meanwhile and
# the core round trip just before (core_round_trip)
run_logged() {
  local log="$1"; shift
  local a b t0 t1 rt rc=0
  rt="$(core_round_trip)"
  a=($(busy_jiffies)); t0="$(date +%s.%N)"
  /usr/bin/time -f 'OWN_CPU_S %U %S MAXRSS_KB %M' -o "$log.cpu" "$@" >"$log" 2>&1 || rc=$?
  t1="$(date +%s.%N)"; b=($(busy_jiffies))
  python3 - "$log" "$t0" "$t1" "${a[0]}" "${b[0]}" "$HZ" "$rt" <<'PY'
import sys
log, t0, t1, a, b, hz = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5]), int(sys.argv[6])
rt = sys.argv[7]
own, rss = 0.0, 0
try:
    for line in open(log + ".cpu"):
        if line.startswith("OWN_CPU_S"):
            w = line.split(); own = float(w[1]) + float(w[2]); rss = int(w[4])
except (OSError, IndexError, ValueError):
    pass
wall = t1 - t0
other = max(0.0, ((b - a) / hz - own) / wall) if wall > 0 else 0.0
open(log + ".load", "w").write(f"wall_s {wall:.2f} own_cpu_s {own:.2f} maxrss_kb {rss} other_cores {other:.2f} core_round_trip_ns {rt}\n")
PY
  return $rc
}

# memory_latency: the machine's load-to-use time by working set, one line ("32 KiB 1.4 ns, ...;
# other load 0.01 cores"; bench/memory_latency.c, compiled once into a temporary folder, ~8 s); "?"
# with no C compiler. The other load is the CPU other processes used meanwhile (run_logged): a busy machine's
# figures are not its latencies (one busy core took the 256 KiB figure from 4 to 23 ns here).
memory_latency() {
  if [[ -z "${MEM_LAT_BIN:-}" ]]; then
    MEM_LAT_BIN="$(mktemp -d)/memory_latency"
    cc -O2 "$HERE/memory_latency.c" -o "$MEM_LAT_BIN" 2>/dev/null || MEM_LAT_BIN=false
  fi
  if [[ "$MEM_LAT_BIN" == false ]]; then echo "?"; return; fi
  local line="?" other="?"
  if run_logged "$MEM_LAT_BIN.log" "$MEM_LAT_BIN"; then line="$(head -n 1 "$MEM_LAT_BIN.log")"; fi
  other="$(awk '{for (i = 1; i < NF; ++i) if ($i == "other_cores") print $(i + 1)}' "$MEM_LAT_BIN.log.load" 2>/dev/null)"
  echo "$line; other load ${other:-?} cores"
}

# machine_description: the machine and the build the figures come from, first in every results.txt:
# the CPU (model name, vendor, family / model / stepping), the CPUs, each cache level's size and how
# many CPUs share it, the memory, whether it is a virtual machine, transparent huge pages, the kernel;
# the load-to-use time by working set (memory_latency: what the caches reach, which the sizes above
# do not say; measured after the timed runs, not beside them); and the grainscale binary's `version`
# line (revision, compiler, instruction set, optimised or not). The same code's figures differ by
# tens of per cent between machines (docs/performance.md), so a figure is only comparable with one
# from the same machine.
machine_description() {
  python3 - "${GS:-}" "$(memory_latency)" <<'PY'
import os, subprocess, sys
gs = sys.argv[1]
info = {}
try:
    for line in open("/proc/cpuinfo"):
        k, _, v = line.partition(":")
        k = k.strip()
        if k and k not in info:
            info[k] = v.strip()
except OSError:
    pass
def size_text(s):  # sysfs writes "48K", "2048K", "491520K"
    if s.endswith("K") and s[:-1].isdigit():
        kib = int(s[:-1])
        return f"{kib // 1024} MiB" if kib >= 1024 and kib % 1024 == 0 else f"{kib} KiB"
    return s
caches = []
base = "/sys/devices/system/cpu/cpu0/cache"
try:
    for d in sorted(os.listdir(base)):
        if not d.startswith("index"):
            continue
        r = lambda f: open(os.path.join(base, d, f)).read().strip()
        try:
            level, kind, size, shared = r("level"), r("type"), r("size"), r("shared_cpu_list")
        except OSError:
            continue
        if kind == "Instruction":
            continue
        n = sum(int(b) - int(a) + 1 if "-" in p else 1
                for p in shared.split(",") for a, _, b in [p.partition("-")])
        name = f"L{level}" + ("d" if kind == "Data" else "")
        caches.append(f"{name} {size_text(size)} ({'per CPU' if n == 1 else f'shared by {n} CPUs'})")
except OSError:
    pass
mem = "?"
try:
    for line in open("/proc/meminfo"):
        if line.startswith("MemTotal:"):
            mem = f"{int(line.split()[1]) / 1024 / 1024:.1f} GiB"
except OSError:
    pass
thp = "?"
try:
    t = open("/sys/kernel/mm/transparent_hugepage/enabled").read()
    thp = t[t.index("[") + 1:t.index("]")]
except (OSError, ValueError):
    pass
vm = "a virtual machine" if "hypervisor" in info.get("flags", "").split() else "not a virtual machine"
cpu = (f"{info.get('model name', '?')} ({info.get('vendor_id', '?')} family {info.get('cpu family', '?')} "
       f"model {info.get('model', '?')} stepping {info.get('stepping', '?')})")
print(f"machine: {cpu}, {os.cpu_count()} CPUs, {vm}; caches {', '.join(caches) or '?'}; memory {mem}; "
      f"transparent huge pages {thp}; Linux {os.uname().release}")
print(f"latency: {sys.argv[2]} (a load's wait by working set, a pointer chase: bench/memory_latency.c)")
if gs:
    try:
        v = subprocess.run([gs, "version"], capture_output=True, text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        v = ""
    print(f"build: {v or gs + ' (its version unknown)'}")
PY
}

# kept_state WHAT CKPT LOG ARGS...: the state CKPT as an earlier call kept it (FRESH=1: made again), or
# made now, untimed, by `grainscale bench ARGS... --settled CKPT` (its output in LOG); WHAT names the
# state in the messages ("poured state", "N = 1000: settled state").
kept_state() {
  local what="$1" ckpt="$2" log="$3"; shift 3
  if [[ "${FRESH:-0}" == 1 ]]; then rm -f "$ckpt"; fi
  if [[ -f "$ckpt" ]]; then
    say "$what from $ckpt (FRESH=1 to make it again)"
  else
    say "$what: making it (untimed; progress in $log) -> $ckpt"
    run_logged "$log" "$GS" bench "$@" --settled "$ckpt" || die "making the $what failed; see $log"
  fi
}

# yaml_with SRC DST KEY=VALUE ...: copy scenario SRC to DST with the first `KEY: value` outside comments
# replaced for each KEY (scalars only, e.g. end=0.05 count=500),
# and the materials/shape/file paths made absolute, so DST runs from any folder.
yaml_with() {
  local src="$1" dst="$2"; shift 2
  python3 - "$src" "$dst" "$@" <<'PY' || die "could not write $2 from $1"
import os, re, sys
src, dst, subs = sys.argv[1], sys.argv[2], sys.argv[3:]
base = os.path.dirname(os.path.abspath(src))
def absolute(m):
    p = m.group(2)
    return m.group(1) + (p if os.path.isabs(p) else os.path.normpath(os.path.join(base, p)))
todo = dict(s.split("=", 1) for s in subs)
lines = []
for line in open(src).read().split("\n"):
    code, hash_, comment = line.partition("#")          # leave comments alone
    code = re.sub(r"((?:materials|shape|file):\s*)([^\s,}]+)", absolute, code)
    for k in list(todo):
        code, n = re.subn(r"(\b" + re.escape(k) + r":\s*)([^\s,}]+)", lambda m: m.group(1) + todo[k], code, count=1)
        if n: del todo[k]
    lines.append(code + hash_ + comment)
if todo:
    sys.exit(f"keys {sorted(todo)} not found in {src}")
t = "\n".join(lines)
open(dst, "w").write(t)
PY
}
