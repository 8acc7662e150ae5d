// Recorded motion CSV (dem/motion/tabulated_motion.hpp), evaluated inside and outside its span.
#include "dem/input_error.hpp"
#include "dem/motion/tabulated_motion.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed_motion.csv");
  try {
    const auto m = grainscale::dem::TabulatedMotion::load(path);
    for (double t : {-1.0, 0.0, 0.5, 1.7, 1e9}) (void)m.at(t);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
