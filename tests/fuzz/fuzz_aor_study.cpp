// Angle-of-repose calibration study YAML (studies/aor_study.hpp), then each case's AOR run settings
// and the scenario they make. Bad input must end in InputError. The work folder holds materials.yaml
// (materials grain, wall) and shape.yaml.
#include "dem/input_error.hpp"
#include "fuzz_input_file.hpp"
#include "studies/aor_rig.hpp"
#include "studies/aor_study.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace grainscale;
  const std::string path = fuzz::input_file(data, size, "fuzzed_study.yaml");
  try {
    const studies::CalibrationStudy s = studies::load_calibration_study(path);
    for (const studies::CalibrationCase& c : s.cases) {
      const studies::AorCase a = studies::aor_case(s, c, s.seeds.front(), s.materials_file);
      (void)studies::aor_scenario_yaml(a, (fuzz::work_dir() / "aor_out").string());
    }
  } catch (const InputError&) {
  }
  return 0;
}
