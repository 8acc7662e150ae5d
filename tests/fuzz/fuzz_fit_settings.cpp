// `grainscale fit` settings YAML (studies/fit_command.hpp): the fit's keys plus the continuum model
// and data files they name (continuum.yaml, fields.csv, coverage.csv in the work folder). Bad input
// must end in InputError.
#include "dem/input_error.hpp"
#include "fuzz_input_file.hpp"
#include "studies/fit_command.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed_fit.yaml");
  try {
    (void)grainscale::studies::load_fit_command_settings(path);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
