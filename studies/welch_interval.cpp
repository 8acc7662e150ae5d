#include "studies/welch_interval.hpp"

#include <gsl/gsl_cdf.h>

#include <cmath>
#include <limits>

namespace grainscale::studies {

SampleStats sample_stats(const std::vector<double>& values) {
  SampleStats s;
  double sum = 0;
  for (double v : values) {
    if (std::isfinite(v)) sum += v, ++s.n;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.mean = s.n > 0 ? sum / s.n : nan;
  if (s.n < 2) {
    s.sd = nan;
    return s;
  }
  double ss = 0;  // two passes: no cancellation
  for (double v : values) {
    if (std::isfinite(v)) ss += (v - s.mean) * (v - s.mean);
  }
  s.sd = std::sqrt(ss / (s.n - 1));
  return s;
}

WelchInterval welch_interval(const SampleStats& a, const SampleStats& b, double confidence) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  WelchInterval w;
  w.difference = b.mean - a.mean;
  w.standard_error = w.dof = w.half_width = w.lo = w.hi = nan;
  if (a.n < 2 || b.n < 2 || !std::isfinite(w.difference)) return w;
  w.defined = true;
  const double va = a.sd * a.sd / a.n, vb = b.sd * b.sd / b.n;
  w.standard_error = std::sqrt(va + vb);
  if (w.standard_error == 0) {
    w.dof = a.n + b.n - 2;
    w.half_width = 0;
  } else {
    w.dof = (va + vb) * (va + vb) / (va * va / (a.n - 1) + vb * vb / (b.n - 1));
    w.half_width = gsl_cdf_tdist_Pinv(0.5 * (1 + confidence), w.dof) * w.standard_error;
  }
  w.lo = w.difference - w.half_width;
  w.hi = w.difference + w.half_width;
  w.excludes_zero = w.lo > 0 || w.hi < 0;
  return w;
}

}  // namespace grainscale::studies
