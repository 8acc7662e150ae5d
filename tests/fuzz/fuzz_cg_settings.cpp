// Coarse-graining settings YAML (coarsegrain/cg_settings.hpp): bad input must end in InputError.
// The work folder has a snapshots/ folder for `snapshot_dir: snapshots`.
#include "coarsegrain/cg_settings.hpp"
#include "dem/input_error.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "cg.yaml");
  try {
    (void)grainscale::cg::load_cg_settings(path);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
