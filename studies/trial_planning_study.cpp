#include "studies/trial_planning_study.hpp"

#include <cstdio>
#include <filesystem>

#include "studies/study_folder.hpp"
#include "studies/trial_plan_settings.hpp"
#include "studies/trial_report.hpp"
#include "studies/trial_sweep_run.hpp"

namespace grainscale::studies {

std::string run_trial_planning_study(const std::string& file, const StudyOptions& options) {
  const double t0 = wall_seconds_now();
  const TrialPlanSettings s = load_trial_plan_settings(file);
  const std::string out = options.output_override.empty() ? s.output_directory : options.output_override;
  StudyFolder folder(out, s.inputs);
  std::vector<TrialStage> stages;
  stages.push_back({"settings", std::to_string(s.designs.size()) + " designs, " + std::to_string(s.variants.size()) +
                                    " variants checked", wall_seconds_now() - t0});
  folder.log("trial_planning " + s.name + ": " + stages.back().what);
  for (const auto& e : s.excluded) folder.log("variant " + e.name + " left out: " + e.reason);

  const double t1 = wall_seconds_now();
  const TrialSweepResult r = run_trial_sweep(s, options.threads, [&](const std::string& line) { folder.log(line); });
  char what[160];
  std::snprintf(what, sizeof what, "%zu hold predictions of %.0f s on %d threads", s.designs.size() * s.variants.size(),
                s.duration, r.threads);
  stages.push_back({"sweep", what, wall_seconds_now() - t1});
  folder.log(std::string("sweep done: ") + what);

  const std::string report = write_trial_report(s, r, stages, folder.directory());
  folder.log("report: " + report);
  return report;
}

}  // namespace grainscale::studies
