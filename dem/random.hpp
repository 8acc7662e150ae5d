#pragma once
// Seeded random numbers that are identical on every platform and standard library: std::mt19937_64
// is fully specified, but std::uniform_real_distribution is not, so the conversion to [0, 1) is ours.
#include <cstdint>
#include <random>

namespace grainscale::dem {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace grainscale::dem
