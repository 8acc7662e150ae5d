// Scenario YAML: load_scenario validates every key; bad input must end in InputError, nothing else.
#include "dem/input_error.hpp"
#include "dem/scenario.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "scenario.yaml");
  try {
    const grainscale::dem::Scenario s = grainscale::dem::load_scenario(path);
    (void)grainscale::dem::scenario_fingerprint(s);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
