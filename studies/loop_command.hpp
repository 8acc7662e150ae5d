#pragma once
// `grainscale loop SETTINGS.yaml`: close the loop between a fitted continuum model and measured data
// (issue 9, docs/loop.md). (1) Fit the current model (the base) and compute the residual; (2)
// diagnose the residual (loop_diagnosis.hpp); (3) rank candidate effects (loop_candidates.hpp) by
// refitting base + candidate with an information criterion and blocked cross-validation
// (loop_ranking.hpp); (4) add the winner, if one is justified, and report the error before and
// after with figures (loop.yaml, report.md, PNGs).
//
//   fit: fit.yaml            a `grainscale fit` settings file: the model, the data (CSV, or a
//                            `grainscale cg` fields.h5 as data.fields) and the base parameters
//   scenario: platform.yaml  optional DEM scenario: motion period, <ω²>, pauses, rotation axis
//   container: box           optional: the wall whose motion counts (default: the first moving one)
//   candidates: [surface_drift, lever_arm]   or {lever_arm: {axis_x: -0.6}} or absent: all
//   cv: {by: auto, blocks: 4}                time | x | auto
//   selection: {min_cv_gain: 0.02, bic_drop: 10}
//   diagnosis: {period: 18, surface_layer: 0.01, wall_band: 0.08, max_lag: 8, alpha: 0.01}
//   candidate_iterations: 40
//   output: loop_out
#include <optional>
#include <string>
#include <vector>

#include "studies/fit_command.hpp"
#include "studies/loop_candidates.hpp"
#include "studies/loop_diagnosis.hpp"
#include "studies/loop_motion.hpp"
#include "studies/loop_ranking.hpp"

namespace grainscale::studies {

struct LoopSettings {
  std::string source_file;
  FitCommandSettings fit;               // model, data, base parameters, fit options
  std::string scenario_file, container;
  std::optional<MotionFacts> motion;    // from the scenario
  std::vector<Candidate> candidates;
  CvSettings cv;
  double min_cv_gain = 0.02, bic_drop = 10;  // relative drop of the held-out chi2; BIC drop
  DiagnosisSettings diagnosis;
  int candidate_iterations = 40;
  std::string output_folder;
};

/// Read and check; every problem is an InputError naming file, line and key.
LoopSettings load_loop_settings(const std::string& yaml_file);

struct LoopResult {
  Evaluation base;
  Diagnosis diagnosis_before, diagnosis_after;
  std::vector<Evaluation> candidates;  // sorted by CV error (failed ones last)
  int chosen = -1;                     // index into candidates, -1: none added
  std::string reason;                  // why this one, or why none
  std::vector<std::string> files;
  Observations data;
};

LoopResult run_loop(const LoopSettings& settings);

/// `grainscale loop SETTINGS.yaml [--out DIR]`; prints a summary, returns 0.
int loop_command(const std::vector<std::string>& positional, const std::string& out);

}  // namespace grainscale::studies
