#include "studies/trial_discrimination.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grainscale::studies {

double separation(const PredictedObservation& a, const PredictedObservation& b, const DiscriminationSettings& s) {
  const double l = (a.left - b.left) / s.sigma_end, c = (a.centre - b.centre) / s.sigma_centre,
               r = (a.right - b.right) / s.sigma_end;
  return std::sqrt(l * l + c * c + r * r);
}

std::vector<TrialScore> score_trials(const std::vector<std::vector<PredictedObservation>>& predictions,
                                     const DiscriminationSettings& s) {
  std::vector<TrialScore> out;
  for (std::size_t d = 0; d < predictions.size(); ++d) {
    const auto& p = predictions[d];
    TrialScore t;
    t.design = static_cast<int>(d);
    double sum = 0, least = std::numeric_limits<double>::infinity();
    int pairs = 0;
    for (std::size_t a = 0; a < p.size(); ++a) {
      for (std::size_t b = a + 1; b < p.size(); ++b) {
        double sep = separation(p[a], p[b], s);
        if (!std::isfinite(sep)) sep = 0;  // a failed prediction separates nothing
        sum += sep;
        ++pairs;
        if (sep < least) least = sep, t.pair_a = static_cast<int>(a), t.pair_b = static_cast<int>(b);
      }
    }
    t.min_pair = pairs ? least : 0;
    t.mean_pair = pairs ? sum / pairs : 0;
    t.score = s.score == "mean" ? t.mean_pair : t.min_pair;
    out.push_back(t);
  }
  std::stable_sort(out.begin(), out.end(), [](const TrialScore& a, const TrialScore& b) { return a.score > b.score; });
  return out;
}

std::vector<TrialScore> recommended_trials(const std::vector<TrialScore>& ranked, const DiscriminationSettings& s) {
  std::vector<TrialScore> out;
  for (const auto& t : ranked) {
    if (static_cast<int>(out.size()) >= s.top) break;
    if (t.score >= s.min_separation && t.score > 0) out.push_back(t);
  }
  return out;
}

}  // namespace grainscale::studies
