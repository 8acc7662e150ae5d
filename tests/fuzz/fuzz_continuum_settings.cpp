// Continuum settings YAML (continuum/settings.hpp): the reader, which also builds the model once (term
// registry, flow, grid), then the initial field and output times. Bad input must end in InputError.
// The work folder holds flow.h5 (a valid gridded flow) for `flow: {type: file, file: flow.h5}`.
#include "continuum/settings.hpp"
#include "dem/input_error.hpp"
#include "fuzz_flow_file.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool flow_file = [] {
    grainscale::fuzz::write_valid_flow_file((grainscale::fuzz::work_dir() / "flow.h5").string());
    return true;
  }();
  (void)flow_file;
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed_continuum.yaml");
  try {
    const grainscale::continuum::ContinuumSettings s = grainscale::continuum::load_continuum_settings(path);
    const grainscale::continuum::Model model = grainscale::continuum::build_model(s);
    (void)grainscale::continuum::initial_field(s, model.grid());
    (void)grainscale::continuum::output_times(s);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
