#pragma once
// The study file of a `trial_planning` study (docs/studies.md, "trial_planning"): the base hold
// settings, the named motions, the sweep (one grid or a list of grids, expanded to designs), the
// duration, the observation of coverage, the model variants and the discrimination settings. Read
// with YamlMap: unknown keys, empty axes and out-of-range values are InputErrors naming file and key;
// every design's motion and every variant is built once at load time, so a bad case cannot fail
// half-way through the sweep.
#include <string>
#include <vector>

#include "studies/hold_settings.hpp"
#include "studies/trial_design.hpp"
#include "studies/trial_discrimination.hpp"
#include "studies/trial_variants.hpp"

namespace grainscale::studies {

struct TrialPlanSettings {
  std::string source_file, name, title, description;
  std::string base_file;                   // a `grainscale hold` settings file
  HoldSettings base;
  std::vector<TrialMotion> motions;        // "base" first
  std::vector<TrialDesign> designs;        // the sweep, expanded, duplicates removed
  std::vector<std::string> swept;          // axes that vary: "motion", "length", ...
  std::vector<std::string> heat_map;       // the two numeric axes of the heat map (empty: the first two swept)
  double duration = 0;                     // [s]
  long resolve = 0, average_cycles = 10;   // resolved cycles (0: all), cycles averaged
  double kappa = 0, delta = 0, end_length = 0.1;  // coverage (continuum/observation.hpp) and zones
  std::vector<TrialVariant> variants;      // the first is the reference (ranking)
  std::vector<ExcludedVariant> excluded;
  std::string loop_file, loop_chosen, loop_reason;
  double max_delta_bic = 10;
  bool constrained_only = true;
  DiscriminationSettings discrimination;
  std::string sigma_source;                // where the σ came from, for the report
  std::string output_directory;
  std::vector<std::string> inputs;         // files to copy into inputs/
};

TrialPlanSettings load_trial_plan_settings(const std::string& file);

/// The motion a design names.
const TrialMotion& motion_of(const TrialPlanSettings& s, const TrialDesign& d);

}  // namespace grainscale::studies
