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
// So grainscale waits with a short spin unless the user has chosen a policy.
//
// libgomp reads the variable once, when it is loaded (before main), so setting it later has no
// effect; the program re-executes itself with the variable set. OMP_WAIT_POLICY or GOMP_SPINCOUNT
// already set (to anything) is respected.
namespace grainscale::studies {

/// Spin iterations before a waiting OpenMP thread sleeps, unless the user chose a policy.
inline constexpr const char* kDefaultSpinCount = "300";

/// Call first thing in main(). Returns only if no re-execution was needed or it failed (then the
/// program goes on with libgomp's default).
void prefer_short_openmp_spin(char** argv);

}  // namespace grainscale::studies
