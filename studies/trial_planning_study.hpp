#pragma once
// `grainscale study FILE.yaml` with `kind: trial_planning` (docs/studies.md, "trial_planning"; issue
// 10, study 6): a sweep of candidate physical trials (container length, fill depth, tilt amplitude and
// period, named motions) predicted with the hold-scale model under each plausible model variant of
// `grainscale loop`, ranked by predicted congregation, and the trials that would best tell the
// variants apart named. Read as the algorithm:
//   load_trial_plan_settings()   every design and variant built and checked   (trial_plan_settings.hpp)
//   run_trial_sweep()            designs x variants, OpenMP, progress + ETA   (trial_sweep_run.hpp)
//   write_trial_report()         CSV, PNG, report.md                          (trial_report.hpp)
#include <string>

#include "studies/study_run.hpp"

namespace grainscale::studies {

/// The study kind's runner: returns the path of report.md.
std::string run_trial_planning_study(const std::string& study_file, const StudyOptions& options);

}  // namespace grainscale::studies
