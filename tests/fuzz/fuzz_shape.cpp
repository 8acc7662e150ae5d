// Clump shape YAML (dem/shape.hpp), and the mass properties of what it accepts.
#include "dem/input_error.hpp"
#include "dem/mass_properties.hpp"
#include "dem/shape.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed_shape.yaml");
  try {
    const grainscale::dem::Shape s = grainscale::dem::load_shape(path);
    (void)grainscale::dem::union_mass_properties(s.spheres);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
