#pragma once
// What the running binary was built with: the compiler, the instruction set it was allowed
// (-march=native gives this CPU's, GRAINSCALE_NATIVE=OFF the x86-64 baseline), OpenMP, whether it
// was optimised and whether assertions are on. `grainscale version` prints it, and every benchmark
// records it beside its figures (bench/lib_bench.sh): the same code runs 12 % faster with the native
// instruction set (docs/performance.md, "Build flags") and several times slower unoptimised, so a
// figure without its build cannot be compared with another.
#include <string>

namespace grainscale::dem {

/// e.g. "GCC 12.2.0, x86-64 with AVX-512, OpenMP 201511, optimised, assertions off".
std::string build_description();

/// "grainscale <version> (<git revision>); <build_description()>": what `grainscale version` prints
/// and the first line of a DEM run's log.
std::string version_line();

}  // namespace grainscale::dem
