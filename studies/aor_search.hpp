#pragma once
// The calibration search: find t in [0, 1] where a measured angle equals a target, given that the
// angle rises with t (more sliding or rolling friction, a steeper pile; Zhou et al. 2002 and
// Roessler et al. 2019 show the angle of repose rising monotonically with both, until it saturates).
// Each evaluation is a whole DEM run, so the search is frugal and tolerant of noise:
//
//   1. Start at `start` (where the materials file's value lies in the range).
//   2. Until the target is bracketed, step towards it: by the secant through the last two points when
//      their slope is positive, else by `first_step`, doubling each time; stop at the ends of the range
//      (then the target is outside it, which is reported).
//   3. Once bracketed, take the secant (regula falsi) point, kept at least 10 % of the bracket's width
//      from either end so that noise in one run cannot stall the search at a bracket end.
//   4. Stop when a run is within `tolerance` of the target, the budget of runs is spent, or the bracket
//      is narrower than `min_width` (the noise floor: closer runs cannot be told apart).
//
// The answer is the run closest to the target; with a bracket, also the linear interpolation between
// its ends (which no run has verified).
#include <functional>
#include <string>
#include <vector>

namespace grainscale::studies {

struct SearchSettings {
  double target = 0;        // deg
  double tolerance = 0.5;   // deg
  int max_runs = 6;
  double start = 0.5;       // t of the first run
  double first_step = 0.25;
  double min_width = 0.01;  // in t
};

struct SearchPoint {
  double t = 0;
  double angle = 0;  // deg; NaN if the run gave no angle
};

struct SearchResult {
  std::vector<SearchPoint> points;  // in the order run
  int best = -1;                    // index of the point closest to the target
  bool converged = false;           // best is within tolerance
  bool bracketed = false;
  double interpolated_t = 0;        // between the final bracket's ends (= best's t without a bracket)
  std::string status;               // one sentence: why the search stopped
};

/// `angle_at(t)` runs one evaluation (NaN: it failed; the search then stops).
SearchResult bracketed_search(const std::function<double(double)>& angle_at, const SearchSettings& settings);

}  // namespace grainscale::studies
