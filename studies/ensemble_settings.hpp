#pragma once
// An ensemble study file (`grainscale study FILE.yaml` with `kind: ensemble`): named variants of one
// experiment, each run over the same list of seeds, measured the same way and compared with a
// reference variant (docs/studies.md, "Ensemble studies"). Issue 10's studies 3 and 4 are ensembles:
//   split_2x400  the report's 800 mm box against the same box split into 2 x 400 mm compartments
//                ("splitting the length of the container in half ... 2x 400mm containers side by side",
//                SAGIT USA120 final report, p. 17; congregation index over seeds);
//   scale_check  one reduced case at 1x and 2x particle size (docs/scaling.md: is 2x valid here?).
//
// A variant is an ordinary DEM scenario (docs/scenario.md); a run writes it again with `seed` (and,
// if the variant says so, `scale_factor`) replaced, so seeds and scales never need copies of files.
// Read with dem/yaml_map.hpp: unknown keys, wrong types and out-of-range values are InputErrors
// naming the file, the line and the key. Relative paths are relative to the study file.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "studies/aor_rig.hpp"

namespace grainscale::studies {

/// One way of running the experiment.
struct EnsembleVariant {
  std::string name;                    // a word: names the variant's folder
  std::string label;                   // for tables and legends (default: name)
  std::string scenario;                // resolved path of its DEM scenario
  std::optional<double> scale_factor;  // replaces the scenario's scale_factor (docs/scaling.md)
};

/// The angle-of-repose test run per variant at its scale (studies/aor_rig.hpp; docs/aor_calibration.md).
struct EnsembleAor {
  AorRig rig;
  AorTiming timing;
  AorGrain grain;              // material, shape, mass (kg, the same at every scale)
  std::string rolling_model = "constant_torque";
  double max_overlap = 0.5;
};

/// What the verdict answers.
enum class EnsembleQuestion {
  congregation,  // does a variant change the congregation index, and by how much (split_2x400)
  scale,         // do the variants agree on every measure within the seed spread (scale_check)
};

struct EnsembleSettings {
  std::string source_file;  // the study file, as given
  std::string name, title, description;
  EnsembleQuestion question = EnsembleQuestion::congregation;
  std::vector<EnsembleVariant> variants;
  std::vector<std::uint64_t> seeds;
  std::optional<double> end_time;  // s: replaces every variant's time.end (shortens or extends a study)
  std::string reference;    // the variant the others are compared with (default: the first)
  double confidence = 0.95; // of the intervals on differences (Welch)
  std::string cg_settings;  // resolved path: snapshots and output are set per run
  double motion_from = 0;   // s: the motion starts (the "before" snapshot; surface flow from here)
  std::optional<EnsembleAor> aor;
  std::string output_directory;  // resolved
};

/// Throws InputError naming the file, line and key (unknown key, no seeds, a variant named twice,
/// a missing scenario, an unknown reference, a coarse-graining grid that is not 2-D).
EnsembleSettings load_ensemble_settings(const std::string& yaml_file);

const char* name(EnsembleQuestion q);

}  // namespace grainscale::studies
