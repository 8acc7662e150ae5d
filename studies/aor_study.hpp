#pragma once
// A calibration study file (`grainscale calibrate STUDY.yaml`; format in docs/aor_calibration.md):
// the rig, the scale, the search settings, and one case per material with its target angle and the
// pair properties to search. Loaded with every key checked (dem/yaml_map.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "dem/scaling.hpp"
#include "studies/aor_rig.hpp"

namespace grainscale::studies {

/// One searched pair property and the range it may take (at the run's scale).
struct CalibrationParameter {
  std::string pair;      // "barley-barley"
  std::string property;  // friction | rolling_friction
  double lo = 0, hi = 0;
  std::string label() const { return pair + " " + property; }
};

struct ReferenceAngle {
  std::string label;  // e.g. "report_dem"
  double deg = 0;
};

struct CalibrationCase {
  std::string name;
  AorGrain grain;                 // grain.mass is filled from `count` when that is given
  std::uint64_t count = 0;        // particles to pour (or 0: grain.mass given)
  double target_deg = 0;          // the angle to match
  std::string target_source = "measured";  // what that angle is (e.g. "report_dem"), for the report
  std::vector<ReferenceAngle> references;  // other angles to compare with (reported, not matched)
  std::vector<CalibrationParameter> parameters;  // searched together along one line (docs)
  std::vector<double> calibrated;  // values a calibration found (one per parameter), or empty: the search
                                   // starts there, and the validation test runs them
};

struct CalibrationStudy {
  std::string file, name;
  std::string materials_file;  // absolute
  double scale_factor = 1;
  dem::ScalingRules scaling;   // applied to the materials before the searched values are set
  std::string rolling_model = "constant_torque";
  double max_overlap = 0.3;
  AorRig rig;
  AorTiming timing;
  double pour_rate = 2.0;      // kg/s
  double tolerance_deg = 0.5;
  int max_runs = 6;            // per case (each a run over all seeds)
  std::vector<std::uint64_t> seeds{1};
  std::vector<CalibrationCase> cases;
  std::string output_directory;
};

/// Parse and validate; errors are InputError naming file, line, key and the allowed range.
CalibrationStudy load_calibration_study(const std::string& file);

/// Keeps only the cases named in `names` (in the study's order; empty: all), so that the cases of
/// one study can run as separate processes into separate folders (`grainscale calibrate --case`).
/// A name the study does not have is an InputError naming the study file and the cases it has.
void select_cases(CalibrationStudy& study, const std::vector<std::string>& names);

/// The AOR case of one run: the study's rig and timing, the case's grain, a seed and a materials file.
AorCase aor_case(const CalibrationStudy& study, const CalibrationCase& c, std::uint64_t seed,
                 const std::string& materials_file);

}  // namespace grainscale::studies
