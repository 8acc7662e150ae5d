#pragma once
// Seeded random numbers that are identical on every platform and standard library: std::mt19937_64
// is fully specified, but std::uniform_real_distribution is not, so the conversion to [0, 1) is ours.
#include <cstdint>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace grainscale::dem {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  /// The engine's complete state as text (the standard fixes the format, [rand.req.eng]: the 312
  /// words of state and the position, in decimal), for checkpoints; set_state() takes it back.
  std::string state() const {
    std::ostringstream o;
    o << engine_;
    return o.str();
  }
  /// Throws std::invalid_argument, leaving the generator as it was, if `s` is not such a state.
  void set_state(const std::string& s) {
    std::istringstream in(s);
    std::mt19937_64 e;
    in >> e;
    if (in.fail() || !(in >> std::ws).eof()) throw std::invalid_argument("not a mt19937_64 state");
    engine_ = e;
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace grainscale::dem
