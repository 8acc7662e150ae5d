#include "studies/nice_ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace grainscale::studies {

double nice_step(double span, int target) {
  if (!(span > 0) || !std::isfinite(span)) throw std::invalid_argument("nice_step: the span must be positive and finite");
  const double raw = span / std::max(1, target);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / magnitude;  // in [1, 10)
  // Round to the nearest of 1, 2, 5, 10 on a log scale (geometric midpoints).
  const double nice = f < std::sqrt(2.0) ? 1 : f < std::sqrt(10.0) ? 2 : f < std::sqrt(50.0) ? 5 : 10;
  return nice * magnitude;
}

namespace {

/// Multiples of `step` in [lo, hi], computed as k * step so labels see no accumulated error.
std::vector<double> multiples(double lo, double hi, double step) {
  const double k0 = std::ceil(lo / step - 1e-9), k1 = std::floor(hi / step + 1e-9);
  std::vector<double> v;
  for (double k = k0; k <= k1; ++k) v.push_back(k == 0 ? 0.0 : k * step);
  return v;
}

void check(double lo, double hi, const char* who) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) {
    throw std::invalid_argument(std::string(who) + ": the range must be finite with lo <= hi");
  }
}

}  // namespace

Ticks nice_ticks(double lo, double hi, int target) {
  check(lo, hi, "nice_ticks");
  if (lo == hi) {
    const double pad = lo == 0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= pad;
    hi += pad;
  }
  Ticks t;
  t.step = nice_step(hi - lo, target);
  // k * step can miss an end that is itself a whole step by an ulp: the data end then wins.
  t.lo = std::min(lo, std::floor(lo / t.step + 1e-9) * t.step);
  t.hi = std::max(hi, std::ceil(hi / t.step - 1e-9) * t.step);
  if (t.lo == 0) t.lo = 0.0;  // no -0
  t.values = multiples(t.lo, t.hi, t.step);
  return t;
}

Ticks ticks_within(double lo, double hi, int target) {
  check(lo, hi, "ticks_within");
  if (lo == hi) throw std::invalid_argument("ticks_within: the range has zero width");
  Ticks t;
  t.lo = lo;
  t.hi = hi;
  t.step = nice_step(hi - lo, target);
  t.values = multiples(lo, hi, t.step);
  return t;
}

std::vector<std::string> tick_labels(const Ticks& t) {
  double largest = 0;
  for (double v : t.values) largest = std::max(largest, std::abs(v));
  std::vector<std::string> out;
  char buf[64];
  // Decimals the step needs: 0.2 -> 1, 0.05 -> 2, 5 -> 0.
  auto decimals_for = [](double step) { return std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9))); };
  if (largest > 0 && (largest >= 1e5 || largest < 1e-3)) {
    const int e = static_cast<int>(std::floor(std::log10(largest) + 1e-9));
    const double scale = std::pow(10.0, e);
    const int d = decimals_for(t.step / scale);
    for (double v : t.values) {
      if (std::abs(v) < 1e-9 * t.step) {
        out.push_back("0");
        continue;
      }
      std::snprintf(buf, sizeof buf, "%.*fe%d", d, v / scale, e);
      out.push_back(buf);
    }
    return out;
  }
  const int d = decimals_for(t.step);
  for (double v : t.values) {
    if (std::abs(v) < 1e-9 * t.step) v = 0.0;  // -0 and round-off around zero
    std::snprintf(buf, sizeof buf, "%.*f", d, v);
    out.push_back(buf);
  }
  return out;
}

}  // namespace grainscale::studies
