#pragma once
// Axis ticks at "nice" numbers: 1, 2 or 5 times a power of ten apart, so a reader can interpolate
// between them by eye (Heckbert, "Nice numbers for graph labels", Graphics Gems, 1990), and their
// labels, all with the same number of decimals.
#include <string>
#include <vector>

namespace grainscale::studies {

struct Ticks {
  double lo = 0, hi = 0;       // the axis range
  double step = 0;             // distance between ticks
  std::vector<double> values;  // lo <= v <= hi, increasing, multiples of step
};

/// The nice step for about `target` intervals over a span (> 0).
double nice_step(double span, int target);

/// Ticks over [lo, hi] widened outwards to whole steps (for ranges taken from data). A range of
/// zero width is widened first (by 10 % of the value, or by 1 around 0). Needs finite lo <= hi.
Ticks nice_ticks(double lo, double hi, int target = 5);

/// Ticks inside a fixed range [lo, hi] (lo < hi): the axis keeps exactly that range.
Ticks ticks_within(double lo, double hi, int target = 5);

/// Labels for the ticks: fixed-point with as many decimals as the step needs ("0.25" is never
/// written for a step of 0.2), or "1.5e-6"-style with one shared exponent when the numbers are
/// very small or very large. Never "-0".
std::vector<std::string> tick_labels(const Ticks& ticks);

}  // namespace grainscale::studies
