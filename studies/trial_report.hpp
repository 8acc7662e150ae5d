#pragma once
// What a `trial_planning` study writes (docs/studies.md): predictions.csv (every design under every
// variant), ranking.csv (designs by predicted congregation under the reference variant),
// discrimination.csv (designs by how well they separate the variants), summary.yaml, the figures
// (congregation and discrimination score against each swept variable, a heat map over two of them,
// the predicted coverage of each recommended trial under every variant) and report.md. CSV and YAML
// hold no wall-clock numbers, so the same study gives the same bytes on any thread count.
#include <string>
#include <vector>

#include "studies/trial_discrimination.hpp"
#include "studies/trial_plan_settings.hpp"
#include "studies/trial_sweep_run.hpp"

namespace grainscale::studies {

struct TrialStage {
  std::string name, what;
  double wall_seconds = 0;
};

/// Congregation ranking: design indices ordered by the reference variant's coverage ratio, highest
/// first (failed cases last; ties: lower index first).
std::vector<int> congregation_ranking(const TrialSweepResult& r);

/// The observations every variant predicts for each design ([design][variant]).
std::vector<std::vector<PredictedObservation>> predicted_observations(const TrialSweepResult& r);

/// Writes every file into `out`; returns the path of report.md.
std::string write_trial_report(const TrialPlanSettings& s, const TrialSweepResult& r, const std::vector<TrialStage>& stages,
                               const std::string& out);

}  // namespace grainscale::studies
