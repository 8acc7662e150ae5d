#pragma once
// Which physical trial best tells the plausible model variants apart. Each variant predicts what the
// trial would measure: the top-view chaff coverage of the left end, centre and right end zones after
// the trial's duration (the report's photographs: ../shared/data/source_measurements.yaml). Two
// variants a, b are separated by that trial by the distance of their predictions in units of the
// measurement uncertainty,
//   d_ab = sqrt( Σ_k ((y_a,k − y_b,k) / σ_k)² ),        k = left, centre, right          (D1)
// the χ² distance a fit would see between them (σ_k: the measurement's standard deviation, from the
// measured data's `sigma` column or the study file). A trial's score is the smallest d_ab over all
// pairs ("min": the trial must separate every pair) or their mean ("mean"). A trial discriminates
// when its score reaches `min_separation` (2: a 2σ difference). With one variant, or identical ones,
// every score is 0 and no trial discriminates. The experimental-design idea is the classic one of
// choosing the experiment that maximises the divergence between rival models' predictions
// (Box & Hill 1967, Technometrics 9:57; Atkinson & Fedorov 1975, Biometrika 62:57, "T-optimality").
#include <string>
#include <vector>

namespace grainscale::studies {

/// What one variant predicts a trial measures.
struct PredictedObservation {
  double left = 0, centre = 0, right = 0;  // coverage in the zones
};

struct DiscriminationSettings {
  double sigma_end = 0.1, sigma_centre = 0.05;  // measurement standard deviations of the coverage
  std::string score = "min";                    // "min" or "mean" over the variant pairs
  int top = 5;                                  // how many trials to name
  double min_separation = 2;                    // score (in σ) a trial needs to discriminate
};

/// (D1) between two predictions.
double separation(const PredictedObservation& a, const PredictedObservation& b, const DiscriminationSettings& s);

struct TrialScore {
  int design = 0;        // index of the trial (design)
  double score = 0;      // min or mean of d_ab
  double min_pair = 0, mean_pair = 0;
  int pair_a = -1, pair_b = -1;  // the closest pair (the one that limits "min")
};

/// Scores every design: `predictions[design][variant]`. Sorted by score, highest first (ties: lower
/// design index first).
std::vector<TrialScore> score_trials(const std::vector<std::vector<PredictedObservation>>& predictions,
                                     const DiscriminationSettings& s);

/// The first `top` scores that reach min_separation (empty: no trial discriminates).
std::vector<TrialScore> recommended_trials(const std::vector<TrialScore>& ranked, const DiscriminationSettings& s);

}  // namespace grainscale::studies
