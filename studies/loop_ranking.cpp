#include "studies/loop_ranking.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dem/input_error.hpp"

namespace grainscale::studies {

using continuum::Model;
using continuum::SurfaceCoverage;

namespace {

bool is_observation(const std::string& name) { return name.rfind("observation.", 0) == 0; }

double get(const Model& m, const SurfaceCoverage& o, const std::string& name) {
  return is_observation(name) ? o.parameters().get(name.substr(12)) : m.parameter(name);
}

void set(Model& m, SurfaceCoverage& o, const std::string& name, double v) {
  if (is_observation(name)) o.parameters().set(name.substr(12), v);
  else m.set_parameter(name, v);
}

/// A parameter ("term.name", a name unique among the terms, or "observation.name"): its
/// admissible and prior ranges; nullptr if the model has none of that name.
const continuum::Parameter* find_parameter(const Model& m, const SurfaceCoverage& o, const std::string& name) {
  if (is_observation(name)) {
    for (const auto& p : o.parameters().all())
      if (p.name == name.substr(12)) return &p;
  }
  const auto dot = name.find('.');
  const std::string term = dot == std::string::npos ? "" : name.substr(0, dot), par = name.substr(dot == std::string::npos ? 0 : dot + 1);
  for (const continuum::FluxTerm* t : m.terms()) {
    if (!term.empty() && t->name() != term) continue;
    for (const auto& p : t->parameters().all())
      if (p.name == par) return &p;
  }
  return nullptr;
}

/// The admissible range of a parameter.
std::pair<double, double> admissible(const Model& m, const SurfaceCoverage& o, const std::string& name) {
  const continuum::Parameter* p = find_parameter(m, o, name);
  if (!p) return {-INFINITY, INFINITY};
  return {p->valid_lo, p->valid_hi};
}

/// The observations of block `held_out` (held = true) or of every other block (held = false).
Observations subset(const Observations& data, const std::vector<int>& fold, int held_out, bool held) {
  Observations s = data;
  s.fields.clear();
  s.coverage.clear();
  std::size_t j = 0;
  for (const auto& o : data.fields)
    if ((fold[j++] == held_out) == held) s.fields.push_back(o);
  for (const auto& o : data.coverage)
    if ((fold[j++] == held_out) == held) s.coverage.push_back(o);
  return s;
}

struct Errors {
  double sum_r2 = 0, sum_f2 = 0, max_f = 0, sum_c2 = 0, max_c = 0;
  int n = 0, nf = 0, nc = 0;
  void add(const Prediction& p, const Observations& d) {
    for (const auto& o : d.fields) {
      const double e = p.fields[o.time][o.index] - o.value;
      sum_r2 += e * e / (o.sigma * o.sigma);
      sum_f2 += e * e;
      max_f = std::max(max_f, std::abs(e));
      ++n;
      ++nf;
    }
    for (const auto& o : d.coverage) {
      const double e = p.coverage[o.time][o.index] - o.value;
      sum_r2 += e * e / (o.sigma * o.sigma);
      sum_c2 += e * e;
      max_c = std::max(max_c, std::abs(e));
      ++n;
      ++nc;
    }
  }
};

}  // namespace

std::vector<int> cv_folds(const continuum::Grid& g, const Observations& data, const CvSettings& cv, std::string& by) {
  by = cv.by;
  const int K = cv.blocks;
  if (by == "auto") by = static_cast<int>(data.times.size()) >= K ? "time" : "x";
  std::vector<int> fold;
  auto time_block = [&](std::size_t t) { return static_cast<int>(t * K / data.times.size()); };
  auto x_block = [&](int column) { return column * K / g.nx(); };
  for (const auto& o : data.fields) fold.push_back(by == "time" ? time_block(o.time) : x_block(static_cast<int>(o.index / g.nz())));
  for (const auto& o : data.coverage) fold.push_back(by == "time" ? time_block(o.time) : x_block(static_cast<int>(o.index)));
  return fold;
}

Evaluation evaluate(const std::string& name, const ModelFactory& factory, const std::vector<std::string>& parameters,
                    const Problem& pr) {
  const auto t_start = std::chrono::steady_clock::now();
  Evaluation ev;
  ev.name = name;
  ev.parameters = parameters;
  const Observations& data = *pr.data;
  try {
    Model model = factory.model();
    SurfaceCoverage obs = factory.observation();
    continuum::FitSettings fs = pr.fit;
    fs.parameters = parameters;
    std::vector<double> start;
    for (const auto& p : parameters) start.push_back(get(model, obs, p));
    if (fs.integrator.method == "ssp_rk3" && fs.integrator.max_dt <= 0) {
      // One fixed step for the fit and every fold (continuum/fit.hpp: a smooth forward map).
      const double rate = model.max_rate(pr.start.t0);
      fs.integrator.max_dt = rate > 0 ? 0.5 * fs.integrator.cfl / rate : data.times.back() - pr.start.t0;
    }
    ev.fit = fit_observations(model, obs, pr.start, data, fs);
    ev.values = ev.fit.values;
    ev.standard_errors = ev.fit.standard_errors;
    ev.prediction = predict(model, obs, pr.start, data.times, fs.integrator);
    Errors all;
    all.add(ev.prediction, data);
    ev.chi2 = all.sum_r2;
    ev.n = all.n;
    ev.k = static_cast<int>(parameters.size());
    ev.rms = std::sqrt(all.sum_r2 / all.n);
    if (all.nf) {
      ev.rmse_fields = std::sqrt(all.sum_f2 / all.nf);
      ev.max_fields = all.max_f;
    }
    if (all.nc) {
      ev.rmse_coverage = std::sqrt(all.sum_c2 / all.nc);
      ev.max_coverage = all.max_c;
    }
    const double fit_term = data.sigma_known ? ev.chi2 : ev.n * std::log(ev.chi2 / ev.n);
    ev.aic = fit_term + 2 * ev.k;
    ev.bic = fit_term + ev.k * std::log(static_cast<double>(ev.n));
    if (!ev.fit.converged) ev.warnings.push_back("the fit did not converge (GSL: " + ev.fit.status + ")");
    for (std::size_t j = 0; j < parameters.size(); ++j) {
      const double hi = admissible(model, obs, parameters[j]).second;
      ev.at_bound.push_back(ev.values[j] >= hi * (1 - 1e-3));
      if (ev.at_bound.back()) {
        ev.warnings.push_back(parameters[j] + " ran to the upper end of its admissible range (" + std::to_string(hi) +
                              "): the fit is pressed against a bound, so its standard error means nothing and the term "
                              "stands in for something else");
      } else if (!(ev.values[j] / start[j] > 1e-6)) {
        ev.warnings.push_back(parameters[j] + " ran to " + std::to_string(ev.values[j]) + ": the data do not need it");
      } else if (!(ev.standard_errors[j] < ev.values[j])) {
        ev.warnings.push_back(parameters[j] + ": standard error not below the value (unconstrained)");
      }
      // Far outside the range expected of granular beds (docs/continuum.md, docs/loop.md): the fit
      // may be right, but the value asks for a physical reason before it is believed. A warning
      // only: the priors are not bounds (the validated clustering strength lies above its prior).
      const continuum::Parameter* p = find_parameter(model, obs, parameters[j]);
      const double v = ev.values[j];
      if (p && p->prior_hi > 0 && !ev.at_bound[j] && (v > 3 * p->prior_hi || v < p->prior_lo / 3) && v / start[j] > 1e-6) {
        const bool above = v > p->prior_hi;
        char b[128];
        std::snprintf(b, sizeof b, " = %.3g is %.3gx %s its prior range (%.3g to %.3g): ask what makes it so ", v,
                      above ? v / p->prior_hi : p->prior_lo / v, above ? "above" : "below", p->prior_lo, p->prior_hi);
        ev.warnings.push_back(parameters[j] + b + (above ? "strong" : "weak"));
      }
    }

    // Blocked cross-validation, warm-started at the full-data optimum.
    const std::vector<int> fold = cv_folds(model.grid(), data, pr.cv, ev.cv_by);
    Errors held;
    continuum::FitSettings cvs = fs;
    cvs.max_iterations = std::min(fs.max_iterations, 10);  // from the optimum: a few steps suffice
    for (int b = 0; b < pr.cv.blocks; ++b) {
      const Observations train = subset(data, fold, b, false), test = subset(data, fold, b, true);
      const std::size_t n_train = train.fields.size() + train.coverage.size();
      if (test.fields.empty() && test.coverage.empty()) continue;
      if (n_train <= parameters.size()) continue;
      Model m = factory.model();
      SurfaceCoverage o = factory.observation();
      for (std::size_t j = 0; j < parameters.size(); ++j) set(m, o, parameters[j], std::max(ev.values[j], kRanToZero));
      (void)fit_observations(m, o, pr.start, train, cvs);
      held.add(predict(m, o, pr.start, data.times, cvs.integrator), test);
      ++ev.cv_folds;
    }
    ev.cv_points = held.n;
    if (held.n > 0) {
      ev.cv_error = std::sqrt(held.sum_r2 / held.n);
      if (data.sigma_known) ev.cv_model_error = std::sqrt(std::max(ev.cv_error * ev.cv_error - 1, 0.0));
      if (held.nf) ev.cv_rmse_fields = std::sqrt(held.sum_f2 / held.nf);
      if (held.nc) ev.cv_rmse_coverage = std::sqrt(held.sum_c2 / held.nc);
    }
    ev.ok = true;
  } catch (const std::exception& e) {
    ev.error = e.what();
  }
  ev.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return ev;
}

}  // namespace grainscale::studies
