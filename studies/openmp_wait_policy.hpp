#pragma once
// OpenMP threads that wait at a barrier either spin (libgomp's default: up to ~300,000 spins before
// sleeping) or sleep at once (OMP_WAIT_POLICY=passive). A DEM step has several short parallel
// regions, and on a machine where anything else runs, one of our threads is often descheduled: the
// other then spins for its whole time slice. Measured on the 2-core development machine with other
// jobs running (platform_quick, 2 threads, 40 s each): default 0.55 M sphere-steps/s, GOMP_SPINCOUNT=1e4
// 0.89 M, passive 3.78 M (docs/performance.md). On an idle machine spinning saves a few microseconds
// per barrier, a few per cent at most. Shared machines are the common case, so grainscale waits
// passively unless the user has chosen a policy.
//
// libgomp reads the variable once, when it is loaded (before main), so setting it later has no
// effect; the program re-executes itself with the variable set. OMP_WAIT_POLICY or GOMP_SPINCOUNT
// already set (to anything) is respected.
namespace grainscale::studies {

/// Call first thing in main(). Returns only if no re-execution was needed or it failed (then the
/// program goes on with libgomp's default).
void prefer_passive_openmp_wait(char** argv);

}  // namespace grainscale::studies
