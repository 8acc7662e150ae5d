#pragma once
// How sure an ensemble is of a difference between two variants: each variant's measure over its
// seeds (mean, sample standard deviation, n), and the difference of two means with Welch's interval,
// which does not assume the two variants scatter equally (a 2x and a 1x run need not):
//
//   d = mean_b - mean_a,   se = sqrt(s_a^2 / n_a + s_b^2 / n_b)
//   nu = se^4 / ((s_a^2/n_a)^2 / (n_a - 1) + (s_b^2/n_b)^2 / (n_b - 1))     (Welch-Satterthwaite)
//   interval d +- t_{(1+p)/2, nu} se
//
// Welch, B. L. (1947), "The generalization of 'Student's' problem when several different population
// variances are involved", Biometrika 34:28-35; Satterthwaite, F. E. (1946), Biometrics Bull. 2:110.
// The t quantile is GSL's (gsl_cdf_tdist_Pinv). With fewer than two seeds in a variant there is no
// spread and the interval is undefined (reported as such, never as "no difference").
#include <vector>

namespace grainscale::studies {

struct SampleStats {
  int n = 0;         // finite values
  double mean = 0;   // NaN when n = 0
  double sd = 0;     // sample standard deviation (n - 1); NaN when n < 2
};

/// Over the finite values (NaN and infinities are left out).
SampleStats sample_stats(const std::vector<double>& values);

struct WelchInterval {
  double difference = 0;      // mean_b - mean_a
  double standard_error = 0;  // NaN when undefined
  double dof = 0;             // Welch-Satterthwaite degrees of freedom
  double half_width = 0;      // t quantile x standard error
  double lo = 0, hi = 0;      // the interval
  bool defined = false;       // both variants have n >= 2
  bool excludes_zero = false; // the variants differ by more than their seed spread allows
};

/// The `confidence` (e.g. 0.95) interval of mean_b - mean_a. When both spreads are zero the
/// difference is exact: the interval is the point, and it excludes zero unless the means are equal.
WelchInterval welch_interval(const SampleStats& a, const SampleStats& b, double confidence);

}  // namespace grainscale::studies
