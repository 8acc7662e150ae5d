#pragma once
// `kind: loop` studies (docs/studies.md): `grainscale loop` (loop_command.hpp, docs/loop.md) on a
// measured data set, into the study folder's loop/, with a report.md a user can read without the
// code: the data and where they come from (with the caveats that limit them), the base model's fit,
// the residual diagnosis, the ranked candidate effects, the effect added or why none, the error
// before and after, the figures, and what one data set can and cannot establish
// (loop_study_report.hpp).
//
//   kind: loop
//   name: loop_report_measurements      a word (no '/')
//   title: "..."  description: >...    optional
//   loop: data/wheat_30min_loop.yaml    a `grainscale loop` settings file (its own `output` is replaced)
//   provenance: data/README.md          optional: where the data come from (copied to inputs/, linked)
//   caveats: ["...", "..."]             optional: what limits the data, in words, for the report
//   candidates: [surface_drift]         optional: try only these of the loop file's candidates
//   candidate_iterations: 10            optional: replaces the loop file's (a quicker run)
//   output: {directory: ../runs/loop_report_measurements}
#include <optional>
#include <string>
#include <vector>

#include "studies/loop_command.hpp"
#include "studies/study_run.hpp"

namespace grainscale::studies {

struct LoopStudySettings {
  std::string source_file, name, title, description;
  std::string loop_file;    // resolved
  LoopSettings loop;        // loaded (checked), candidates filtered; output folder set by the runner
  std::string provenance;   // resolved, or empty
  std::vector<std::string> caveats;
  std::string output_directory;  // resolved
};

/// Throws InputError naming file, line and key (unknown keys, a missing loop or provenance file, a
/// candidate the loop file does not try, an empty candidate list).
LoopStudySettings load_loop_study_settings(const std::string& yaml_file);

struct LoopStudyResults {
  LoopResult loop;
  double wall_seconds = 0;
  std::vector<std::string> inputs;  // copied into inputs/ (file names)
};

/// Runs the loop into `<output>/loop/` and writes report.md; `report_path` receives its path.
LoopStudyResults run_loop_study(const LoopStudySettings& s, const StudyOptions& options, std::string& report_path);

/// The study_kinds.cpp runner.
std::string loop_study_runner(const std::string& study_file, const StudyOptions& options);

}  // namespace grainscale::studies
