#include "studies/aor_search.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace grainscale::studies {

SearchResult bracketed_search(const std::function<double(double)>& angle_at, const SearchSettings& s) {
  if (s.max_runs < 1 || !(s.tolerance > 0) || !(s.first_step > 0) || !(s.start >= 0 && s.start <= 1)) {
    throw std::invalid_argument("bracketed_search: max_runs >= 1, tolerance > 0, first_step > 0, start in [0, 1]");
  }
  SearchResult r;
  // Bracket ends: the highest t below the target and the lowest t above it.
  int lo = -1, hi = -1;
  double step = s.first_step;
  double t = s.start;
  auto fmt = [](double v) {
    std::ostringstream o;
    o.precision(4);
    o << v;
    return o.str();
  };
  while (true) {
    const double a = angle_at(t);
    r.points.push_back({t, a});
    const int k = static_cast<int>(r.points.size()) - 1;
    if (std::isnan(a)) {
      r.status = "the run at t = " + fmt(t) + " gave no angle";
      break;
    }
    if (r.best < 0 || std::abs(a - s.target) < std::abs(r.points[r.best].angle - s.target)) r.best = k;
    if (std::abs(a - s.target) <= s.tolerance) {
      r.converged = true;
      r.status = "within " + fmt(s.tolerance) + " deg of the target after " + std::to_string(k + 1) + " runs";
      break;
    }
    if (a < s.target && (lo < 0 || t > r.points[lo].t)) lo = k;
    if (a > s.target && (hi < 0 || t < r.points[hi].t)) hi = k;
    if (static_cast<int>(r.points.size()) >= s.max_runs) {
      r.status = "the budget of " + std::to_string(s.max_runs) + " runs is spent";
      break;
    }
    if (lo >= 0 && hi >= 0 && r.points[lo].t < r.points[hi].t) {
      const SearchPoint &pl = r.points[lo], &ph = r.points[hi];
      const double w = ph.t - pl.t;
      if (w < s.min_width) {
        r.status = "the bracket is narrower than " + fmt(s.min_width) + " in t: runs this close differ by noise";
        break;
      }
      const double secant = pl.t + (s.target - pl.angle) * w / (ph.angle - pl.angle);
      t = std::clamp(secant, pl.t + 0.1 * w, ph.t - 0.1 * w);
      continue;
    }
    if (lo >= 0 && hi >= 0) {
      // The angle fell with t across the target: the noise is larger than the effect of t here.
      r.status = "the angle does not rise with t between t = " + fmt(r.points[hi].t) + " and " + fmt(r.points[lo].t) +
                 ": noise exceeds the parameter's effect";
      break;
    }
    // Not yet bracketed: step towards the target.
    const double dir = a < s.target ? 1.0 : -1.0;
    if ((dir > 0 && t >= 1) || (dir < 0 && t <= 0)) {
      r.status = std::string("the target lies outside the searched range (the angle at the ") +
                 (dir > 0 ? "upper" : "lower") + " end is " + fmt(a) + " deg)";
      break;
    }
    double next = t + dir * step;
    if (k >= 1) {
      const SearchPoint& p = r.points[k - 1];
      const double slope = (a - p.angle) / (t - p.t);
      if (slope > 0 && std::isfinite(slope)) {
        // Secant extrapolation, overshooting by 20 % to bracket rather than creep up on the target,
        // and at most twice the current step.
        const double jump = 1.2 * (s.target - a) / slope;
        next = t + std::clamp(jump, -2 * step, 2 * step);
      }
    }
    step *= 2;
    t = std::clamp(next, 0.0, 1.0);
  }
  r.bracketed = lo >= 0 && hi >= 0 && r.points[lo].t < r.points[hi].t;
  if (r.bracketed) {
    const SearchPoint &pl = r.points[lo], &ph = r.points[hi];
    r.interpolated_t = pl.t + (s.target - pl.angle) * (ph.t - pl.t) / (ph.angle - pl.angle);
  } else {
    r.interpolated_t = r.best >= 0 ? r.points[r.best].t : s.start;
  }
  if (r.converged) r.interpolated_t = r.points[r.best].t;
  return r;
}

}  // namespace grainscale::studies
