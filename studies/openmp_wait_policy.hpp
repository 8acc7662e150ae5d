#pragma once
// OpenMP threads that wait at a barrier spin, then sleep. libgomp's default spin (up to ~300,000
// iterations of `pause`, milliseconds) is ruinous on a shared machine: when one of our threads is
// descheduled the other spins out its whole time slice. Sleeping at once (OMP_WAIT_POLICY=passive)
// costs a futex wake per parallel region, which on a VM is tens of microseconds, several per step.
// A short spin, GOMP_SPINCOUNT=300 (~10-40 us), keeps both: measured on the 2-core VM, clump bed
// (bench/clump_bed.yaml, 14,000 spheres), best of 2 (docs/performance.md, "OpenMP waiting"):
//   idle VM, 2 threads:         passive 13.4 M sphere-steps/s, spin 300 16.5 M, spin 1e4 16.3 M,
//                               active 17.0 M (1 thread: 8.8 M)
//   two same-priority jobs on the other threads: passive 4.8 M, spin 300 5.0 M, spin 1e4 3.5 M (means of 3)
// So grainscale waited with a short spin. On the VM of 2026-12-01 (another CPU, AVX-512) 300 spins
// are too short even when idle: 2 threads 13.5-14.1 M (1.58-1.62x of 1 thread's 8.7 M), spin 3000
// 15.2 M (1.80x), 30,000 15.4 M (1.80x), 300,000 15.5 M (1.82x); with two `yes` jobs beside it,
// spin 300 4.7 / 7.7 M, spin 30,000 4.0 / 4.0 M. So the spin is chosen by the load found at start
// (spin_count_for): the long spin where the machine is idle (nothing but this program runnable,
// by the instantaneous count in /proc/loadavg; the load averages lag by minutes, so a run started
// just after another would be misjudged), the short one otherwise. The choice changes no result (the
// trajectories do not depend on how threads wait), only the speed.
//
// libgomp reads the variable once, when it is loaded (before main), so setting it later has no
// effect; the program re-executes itself with the variable set. OMP_WAIT_POLICY or GOMP_SPINCOUNT
// already set (to anything) is respected.
namespace grainscale::studies {

/// Spin iterations before a waiting OpenMP thread sleeps, unless the user chose a policy: on a
/// shared machine, and on an idle one.
inline constexpr const char* kDefaultSpinCount = "300";
inline constexpr const char* kIdleSpinCount = "30000";

/// The spin count when `runnable` tasks are runnable on the machine, this program included (the
/// fourth field of /proc/loadavg): idle (the long spin) only for exactly 1; 0 means unknown, taken as shared.
const char* spin_count_for(int runnable);

/// Call first thing in main(). Returns only if no re-execution was needed or it failed (then the
/// program goes on with libgomp's default).
void choose_openmp_spin(char** argv);

}  // namespace grainscale::studies
