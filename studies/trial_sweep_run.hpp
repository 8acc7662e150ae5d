#pragma once
// Runs every case of a `trial_planning` study: each design of the sweep under each model variant,
// one hold-scale prediction (studies/hold_run.hpp: the depth-averaged flow closure driving the chaff
// model) per case. Cases are independent and run in parallel with OpenMP (dynamic schedule); each
// writes only its own result slot and every setting is prepared (deep-copied) before the parallel
// loop, so the numbers are bitwise identical for any thread count. Progress with an ETA goes to the
// log. A case that throws (a blow-up, a failed step) is recorded with NaN results and its message,
// and the sweep goes on.
#include <functional>
#include <string>
#include <vector>

#include "studies/trial_discrimination.hpp"
#include "studies/trial_plan_settings.hpp"

namespace grainscale::studies {

/// What one case predicts after the trial's duration.
struct TrialCaseResult {
  PredictedObservation coverage;          // top-view coverage of the left end, centre, right end zones
  double ratio = 0;                       // congregation: mean end coverage / centre coverage
  double share_left = 0, share_right = 0; // share of the chaff in the top layer within the end zone of each wall
  std::vector<double> x, profile;         // coverage along the container at the end
  double chaff_change = 0, c_min = 0, c_max = 0;  // relative change of total chaff; c range
  long resolved_cycles = 0, closure_steps = 0, chaff_steps = 0;
  double seconds = 0;                     // wall clock of the case
  std::string error;                      // set if the case failed
};

struct TrialSweepResult {
  std::vector<std::vector<TrialCaseResult>> cases;  // [design][variant]
  double wall_seconds = 0;
  int threads = 1;
};

/// Mean of `values` over the columns whose centres `x` lie in [a, b] (NaN if none).
double zone_mean(const std::vector<double>& x, const std::vector<double>& values, double a, double b);

/// `threads` <= 0: OpenMP's default. `log` receives progress lines (may be empty).
TrialSweepResult run_trial_sweep(const TrialPlanSettings& s, int threads,
                                 const std::function<void(const std::string&)>& log);

}  // namespace grainscale::studies
