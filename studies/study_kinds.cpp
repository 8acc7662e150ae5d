#include "studies/study_kinds.hpp"

#include <cstdio>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"
#include "studies/trial_planning_study.hpp"
#include "studies/ensemble_run.hpp"
#include "studies/hold_study.hpp"
#include "studies/loop_study.hpp"
#include "studies/option_number.hpp"

namespace grainscale::studies {

namespace {

std::string run_platform_study(const std::string& file, const StudyOptions& options) {
  StudyRun run(load_study_settings(file), options);
  run.setup();
  run.run();
  run.output();
  return run.output_directory() + "/report.md";
}

}  // namespace

const std::vector<StudyKind>& study_kinds() {
  // One line per kind.
  static const std::vector<StudyKind> kinds = {
      {"platform", "DEM -> coarse-graining -> fit -> prediction -> report, one container", run_platform_study},
      {"trial_planning", "sweep of trial designs with the hold-scale model: congregation ranking, trials that discriminate the loop's variants", run_trial_planning_study},
      {"ensemble", "variants x seeds of a DEM experiment: congregation index, bulk density, surface flow, chaff per slice, AOR; differences with intervals", run_ensemble_study},
      {"hold", "hold scenarios (grainscale hold) compared: chaff build-up at the end walls, cost, ranking", hold_study_runner},
      {"loop", "grainscale loop on measured data: fit, residual, ranked effects, error before/after", loop_study_runner},
  };
  return kinds;
}

const StudyKind& study_kind_of(const std::string& study_file) {
  YamlMap root = YamlMap::load_file(study_file);
  const std::string kind = root.string_or("kind", "platform");
  std::string names;
  for (const StudyKind& k : study_kinds()) {
    if (kind == k.name) return k;
    names += std::string(names.empty() ? "" : ", ") + k.name;
  }
  throw InputError(root.where("kind") + ": unknown study kind '" + kind + "' (allowed: " + names + ")");
}

int study_command(const std::vector<std::string>& positional, const std::string& out, const std::string& threads,
                  bool resume) {
  if (positional.size() != 1) throw InputError("usage: grainscale study STUDY.yaml [--out DIR] [--threads N] [--resume]");
  StudyOptions o;
  o.output_override = out;
  o.resume = resume;
  if (!threads.empty()) {
    o.threads = thread_count_option(threads);
  }
  const StudyKind& kind = study_kind_of(positional[0]);
  const std::string report = kind.run(positional[0], o);
  std::printf("study %s: report %s\n", positional[0].c_str(), report.c_str());
  return 0;
}

}  // namespace grainscale::studies
