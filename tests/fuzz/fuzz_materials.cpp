// Materials YAML (dem/material.hpp).
#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed_materials.yaml");
  try {
    (void)grainscale::dem::MaterialTable::load(path);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
