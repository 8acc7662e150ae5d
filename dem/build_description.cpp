#include "dem/build_description.hpp"

#include "grainscale_version.hpp"

namespace grainscale::dem {

// Compiled with the flags of the rest of dem/ (CMakeLists.txt), so the macros below say what the
// simulation code itself was allowed to use.
std::string build_description() {
  std::string s;
#if defined(__clang__)
  s += "Clang " __clang_version__;
#elif defined(__GNUC__)
  s += "GCC " __VERSION__;
#else
  s += "an unknown compiler";
#endif
#if defined(__AVX512F__)
  s += ", x86-64 with AVX-512";
#elif defined(__AVX2__)
  s += ", x86-64 with AVX2";
#elif defined(__x86_64__)
  s += ", x86-64 without AVX2";
#elif defined(__aarch64__)
  s += ", AArch64";
#else
  s += ", an unknown instruction set";
#endif
#if defined(_OPENMP)
  s += ", OpenMP " + std::to_string(_OPENMP);
#else
  s += ", no OpenMP";
#endif
#if defined(__OPTIMIZE__)
  s += ", optimised";
#else
  s += ", not optimised (a Debug build: not for timing)";
#endif
#if defined(NDEBUG)
  s += ", assertions off";
#else
  s += ", assertions on";
#endif
  return s;
}

std::string version_line() {
  return std::string("grainscale ") + version + " (" + git_revision + "); " + build_description();
}

}  // namespace grainscale::dem
