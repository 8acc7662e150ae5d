#include "studies/loop_diagnosis.hpp"

#include <gsl/gsl_cdf.h>

#include "dem/eigen_dense.hpp"
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

namespace grainscale::studies {

std::vector<ResidualPoint> residual_points(const continuum::Grid& g, const Observations& data, const Prediction& p) {
  std::vector<ResidualPoint> out;
  for (const Observation& o : data.fields) {
    ResidualPoint r;
    r.time = o.time;
    r.t = data.times[o.time];
    r.column = static_cast<int>(o.index / g.nz());
    r.layer = static_cast<int>(o.index % g.nz());
    r.x = g.x_centre(r.column);
    r.z = g.z_centre(r.column, r.layer);
    r.model_c = p.fields[o.time][o.index];
    r.error = r.model_c - o.value;
    r.r = r.error / o.sigma;
    out.push_back(r);
  }
  for (const Observation& o : data.coverage) {
    ResidualPoint r;
    r.coverage = true;
    r.time = o.time;
    r.t = data.times[o.time];
    r.column = static_cast<int>(o.index);
    r.layer = g.nz();
    r.x = g.x_centre(r.column);
    r.z = g.h_column(r.column);
    r.model_c = p.fields[o.time][g.index(r.column, g.nz() - 1)];
    r.error = p.coverage[o.time][o.index] - o.value;
    r.r = r.error / o.sigma;
    out.push_back(r);
  }
  return out;
}

SeriesTest whiteness(const std::string& order, const std::vector<std::vector<double>>& series, int max_lag) {
  SeriesTest t;
  t.order = order;
  std::vector<double> all;
  for (const auto& s : series) {
    if (s.size() < 2) continue;
    ++t.series;
    all.insert(all.end(), s.begin(), s.end());
  }
  t.points = static_cast<int>(all.size());
  if (t.points < 8) return t;
  const double mean = std::accumulate(all.begin(), all.end(), 0.0) / all.size();
  double var = 0;
  for (double v : all) var += (v - mean) * (v - mean);
  var /= all.size();
  std::size_t longest = 0;
  for (const auto& s : series) longest = std::max(longest, s.size());
  t.lags = std::min<int>(max_lag, static_cast<int>(longest) / 2);
  for (int k = 1; k <= t.lags; ++k) {
    double sum = 0;
    int n = 0;
    for (const auto& s : series) {
      for (std::size_t j = 0; j + k < s.size(); ++j) {
        sum += (s[j] - mean) * (s[j + k] - mean);
        ++n;
      }
    }
    if (n < 4 || !(var > 0)) {
      t.lags = k - 1;
      break;
    }
    const double rho = sum / n / var;
    t.autocorrelation.push_back(rho);
    t.pairs.push_back(n);
    t.q += n * rho * rho;  // under H0 ρ_k ~ N(0, 1/N_k)
  }
  t.q_p = t.lags > 0 ? gsl_cdf_chisq_Q(t.q, t.lags) : 1.0;
  // Runs of signs about the median, summed over series (Wald & Wolfowitz 1940).
  std::vector<double> sorted = all;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  double e = 0, v = 0;
  for (const auto& s : series) {
    if (s.size() < 2) continue;
    double np = 0, nm = 0;
    int runs = 0, last = 0;
    for (double x : s) {
      if (x == median) continue;
      const int sign = x > median ? 1 : -1;
      (sign > 0 ? np : nm) += 1;
      if (sign != last) ++runs;
      last = sign;
    }
    const double n = np + nm;
    if (np == 0 || nm == 0) {  // one run whatever happens
      e += runs;
      t.runs += runs;
      continue;
    }
    t.runs += runs;
    e += 1 + 2 * np * nm / n;
    v += 2 * np * nm * (2 * np * nm - n) / (n * n * (n - 1));
  }
  t.runs_expected = e;
  if (v > 0) {
    t.runs_z = (t.runs - e) / std::sqrt(v);
    t.runs_p = 2 * gsl_cdf_ugaussian_Q(std::abs(t.runs_z));
  }
  return t;
}

namespace {

Group group(const std::string& name, const std::vector<double>& r) {
  Group g{name, static_cast<int>(r.size()), 0, 0};
  if (r.empty()) return g;
  double s = 0, s2 = 0;
  for (double v : r) {
    s += v;
    s2 += v * v;
  }
  g.mean = s / r.size();
  g.rms = std::sqrt(s2 / r.size());
  return g;
}

/// Residual sum of squares of the least-squares fit of y on the columns of A.
double rss(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  const Eigen::VectorXd beta = A.colPivHouseholderQr().solve(y);
  return (y - A * beta).squaredNorm();
}

std::string pct(double f) {
  std::ostringstream s;
  s.precision(3);
  s << 100 * f << " %";
  return s.str();
}

}  // namespace

Diagnosis diagnose(const continuum::Grid& g, const std::vector<ResidualPoint>& points, const DiagnosisSettings& s) {
  Diagnosis d;
  d.points = static_cast<int>(points.size());
  if (points.empty()) return d;
  double s2 = 0;
  for (const auto& p : points) s2 += p.r * p.r;
  d.rms = std::sqrt(s2 / points.size());

  // Symmetry: key (kind, time, column, layer).
  std::map<std::tuple<bool, std::size_t, int, int>, double> by_cell;
  for (const auto& p : points) by_cell[{p.coverage, p.time, p.column, p.layer}] = p.r;
  double sym = 0, anti = 0;
  for (const auto& [key, a] : by_cell) {
    const auto [cov, time, col, layer] = key;
    const int mirror = g.nx() - 1 - col;
    if (mirror < col) continue;
    const auto it = by_cell.find({cov, time, mirror, layer});
    if (it == by_cell.end()) continue;
    const double b = it->second;
    if (mirror == col) {
      sym += a * a;
    } else {
      sym += 0.5 * (a + b) * (a + b);
      anti += 0.5 * (a - b) * (a - b);
    }
    ++d.mirrored_pairs;
  }
  if (sym + anti > 0) {
    d.symmetric_energy = sym / (sym + anti);
    d.antisymmetric_energy = anti / (sym + anti);
  }

  // Regions.
  const double layer = s.surface_layer > 0 ? s.surface_layer : 0.1 * g.h_column(g.nx() / 2);
  const double band = s.wall_band > 0 ? s.wall_band : 0.1 * g.length();
  std::vector<double> surface, bulk, coverage, wall, interior;
  for (const auto& p : points) {
    if (p.coverage) coverage.push_back(p.r);
    else (p.z >= g.h_column(p.column) - layer ? surface : bulk).push_back(p.r);
    (std::min(p.x, g.length() - p.x) < band ? wall : interior).push_back(p.r);
  }
  d.regions = {group("surface layer (fields)", surface), group("bulk (fields)", bulk), group("coverage", coverage),
               group("near end walls", wall), group("interior", interior)};

  // Harmonics per location.
  if (!(s.period > 0)) {
    d.harmonics_note = "no motion period given (scenario or diagnosis.period)";
  } else {
    std::map<std::tuple<bool, int, int>, std::vector<std::pair<double, double>>> series;
    for (const auto& p : points) series[{p.coverage, p.column, p.layer}].push_back({p.t, p.r});
    std::vector<double> phases;
    for (const auto& p : points) phases.push_back(std::round(1000 * std::fmod(p.t / s.period, 1.0)) / 1000);
    std::sort(phases.begin(), phases.end());
    const int distinct_phases = static_cast<int>(std::unique(phases.begin(), phases.end()) - phases.begin());
    double e0 = 0, e1 = 0, e2 = 0, er = 0;
    for (const auto& [key, ts] : series) {
      if (ts.size() < 6) continue;
      const int n = static_cast<int>(ts.size());
      Eigen::MatrixXd A(n, 5);
      Eigen::VectorXd y(n);
      for (int j = 0; j < n; ++j) {
        const double phi = 2 * M_PI * ts[j].first / s.period;
        A(j, 0) = 1;
        A(j, 1) = std::cos(phi);
        A(j, 2) = std::sin(phi);
        A(j, 3) = std::cos(2 * phi);
        A(j, 4) = std::sin(2 * phi);
        y(j) = ts[j].second;
      }
      const double total = y.squaredNorm(), r0 = rss(A.leftCols(1), y), r1 = rss(A.leftCols(3), y), r2 = rss(A, y);
      e0 += total - r0;
      e1 += r0 - r1;
      e2 += r1 - r2;
      er += r2;
      ++d.harmonic_locations;
    }
    const double total = e0 + e1 + e2 + er;
    if (d.harmonic_locations == 0 || !(total > 0)) {
      d.harmonics_note = "no location has 6 or more observation times";
    } else if (distinct_phases < 5) {
      d.harmonics_note = "the observation times fall on " + std::to_string(distinct_phases) +
                         " phases of the motion: harmonics alias into the mean";
    } else {
      d.harmonics_resolved = true;
      d.mean_energy = e0 / total;
      d.first_harmonic = e1 / total;
      d.second_harmonic = e2 / total;
      d.rest_energy = er / total;
    }
  }

  // Dependence on the model's c: five quantile bins.
  {
    std::vector<std::pair<double, double>> cr;
    for (const auto& p : points) cr.push_back({p.model_c, p.r});
    std::sort(cr.begin(), cr.end());
    const int bins = std::min<int>(5, static_cast<int>(cr.size()));
    for (int b = 0; b < bins; ++b) {
      const std::size_t lo = cr.size() * b / bins, hi = cr.size() * (b + 1) / bins;
      double sc = 0, sr = 0;
      for (std::size_t j = lo; j < hi; ++j) {
        sc += cr[j].first;
        sr += cr[j].second;
      }
      d.c_bin_centre.push_back(sc / (hi - lo));
      d.c_bin_mean_r.push_back(sr / (hi - lo));
      d.c_bin_count.push_back(static_cast<int>(hi - lo));
    }
    double mc = 0, mr = 0;
    for (const auto& [c, r] : cr) {
      mc += c;
      mr += r;
    }
    mc /= cr.size();
    mr /= cr.size();
    double scc = 0, srr = 0, scr = 0;
    for (const auto& [c, r] : cr) {
      scc += (c - mc) * (c - mc);
      srr += (r - mr) * (r - mr);
      scr += (c - mc) * (r - mr);
    }
    d.correlation_with_c = scc > 0 && srr > 0 ? scr / std::sqrt(scc * srr) : 0;
  }

  // Whiteness: ordered in x (per kind, time, layer) and in t (per kind, location).
  {
    std::map<std::tuple<bool, std::size_t, int>, std::vector<std::pair<double, double>>> rows;
    std::map<std::tuple<bool, int, int>, std::vector<std::pair<double, double>>> cols;
    for (const auto& p : points) {
      rows[{p.coverage, p.time, p.layer}].push_back({p.x, p.r});
      cols[{p.coverage, p.column, p.layer}].push_back({p.t, p.r});
    }
    auto to_series = [](auto& m) {
      std::vector<std::vector<double>> out;
      for (auto& [key, v] : m) {
        std::sort(v.begin(), v.end());
        std::vector<double> s;
        for (const auto& [pos, r] : v) s.push_back(r);
        out.push_back(s);
      }
      return out;
    };
    for (auto test : {whiteness("x", to_series(rows), s.max_lag), whiteness("t", to_series(cols), s.max_lag)}) {
      if (test.points >= 8 && test.series > 0) d.tests.push_back(test);
    }
    int n_tests = 0;
    for (const auto& t : d.tests) n_tests += (t.lags > 0) + (t.runs_expected > 0);
    const double level = n_tests > 0 ? s.alpha / n_tests : s.alpha;
    std::ostringstream v;
    for (const auto& t : d.tests) {
      if (t.lags > 0 && t.q_p < level) {
        d.white = false;
        v << "ordered in " << t.order << ": portmanteau Q = " << t.q << " on " << t.lags << " lags, p = " << t.q_p << "; ";
      }
      if (t.runs_expected > 0 && t.runs_p < level) {
        d.white = false;
        v << "ordered in " << t.order << ": " << t.runs << " runs of sign where " << t.runs_expected << " were expected, p = "
          << t.runs_p << "; ";
      }
    }
    d.tested = !d.tests.empty();
    if (d.tests.empty()) {
      d.white = false;
      d.verdict = "untested: too few observations in series (8 or more needed)";
    } else if (d.white) {
      d.verdict = "white: no test rejects at alpha = " + std::to_string(s.alpha) + " (Bonferroni over " +
                  std::to_string(n_tests) + " tests)";
    } else {
      d.verdict = "structured: " + v.str();
    }
  }
  (void)pct;
  return d;
}

}  // namespace grainscale::studies
