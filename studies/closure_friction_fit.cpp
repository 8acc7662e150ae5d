#include "studies/closure_friction_fit.hpp"

#include <gsl/gsl_multimin.h>

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "dem/input_error.hpp"

namespace grainscale::studies {

using continuum::closure::BedFriction;

namespace {

constexpr double kRangeRise = 0.25;  // ΔJ of the sensitivity ranges: (1/2)² of the bar

/// One fittable parameter: its search coordinate (degrees, log10 of ℓ/d, or Δμ), bounds in that
/// coordinate, the grid levels of the first search, the Nelder–Mead initial step and the step of the
/// sensitivity scan.
struct Parameter {
  const char* name;
  double lo, hi;
  std::vector<double> grid;
  double step, scan;
  double (*get)(const BedFriction&);
  void (*set)(BedFriction&, double);
};

const std::vector<Parameter>& parameter_table() {
  static const std::vector<Parameter> table = {
      {"internal_friction_deg", 5, 45, {18, 21, 24, 27, 30}, 1.5, 0.1,
       [](const BedFriction& f) { return f.internal_deg; }, [](BedFriction& f, double v) { f.internal_deg = v; }},
      {"basal_friction_deg", 1, 45, {4, 7, 10, 13, 16}, 1.5, 0.1,
       [](const BedFriction& f) { return f.basal_deg; }, [](BedFriction& f, double v) { f.basal_deg = v; }},
      // log10(ℓ/d): 0.3 to 300 grain diameters.
      {"flowing_layer_diameters", std::log10(0.3), std::log10(300.0), {0, 0.301, 0.602, 0.903, 1.204, 1.806}, 0.15, 0.01,
       [](const BedFriction& f) { return std::log10(f.layer_depth / f.grain_diameter); },
       [](BedFriction& f, double v) { f.layer_depth = f.grain_diameter * std::pow(10.0, v); }},
      {"delta_mu", 0, 10, {0, 0.1, 0.26, 0.5}, 0.05, 0.005,
       [](const BedFriction& f) { return f.delta_mu; }, [](BedFriction& f, double v) { f.delta_mu = v; }},
      {"start_excess_deg", 0, 15, {0, 2, 4, 7}, 1.0, 0.05,
       [](const BedFriction& f) { return f.start_excess_deg; }, [](BedFriction& f, double v) { f.start_excess_deg = v; }},
  };
  return table;
}

/// A parameter's value as reported (ℓ/d itself, not its logarithm).
double shown(const Parameter& p, double coordinate) {
  return std::string(p.name) == "flowing_layer_diameters" ? std::pow(10.0, coordinate) : coordinate;
}

struct Problem {
  std::vector<const Parameter*> params;
  BedFriction base;
  const ClosureRun* run;
  const std::vector<double>* dem_angle;
  const std::vector<double>* dem_speed;
  std::size_t train_end = 0;
  int evaluations = 0;

  BedFriction friction(const std::vector<double>& x) const {
    BedFriction f = base;
    for (std::size_t j = 0; j < params.size(); ++j) params[j]->set(f, std::clamp(x[j], params[j]->lo, params[j]->hi));
    return f;
  }
  /// J on the training frames; outside the bounds J at the nearest bound plus a penalty, so
  /// Nelder–Mead walks back in.
  double objective(const std::vector<double>& x) {
    double outside = 0;
    for (std::size_t j = 0; j < params.size(); ++j) {
      outside += std::max(0.0, params[j]->lo - x[j]) + std::max(0.0, x[j] - params[j]->hi);
    }
    std::vector<double> a, u;
    ++evaluations;
    try {
      (*run)(friction(x), a, u);
    } catch (const std::runtime_error&) {
      return std::numeric_limits<double>::max();  // the motion left the model's range: not a candidate
    }
    const double j = block_errors(*dem_angle, *dem_speed, a, u, 0, train_end).objective;
    return (std::isfinite(j) ? j : std::numeric_limits<double>::max() / 2) + 1e3 * outside;
  }
};

double gsl_objective(const gsl_vector* v, void* data) {
  auto* pr = static_cast<Problem*>(data);
  std::vector<double> x(v->size);
  for (std::size_t j = 0; j < v->size; ++j) x[j] = gsl_vector_get(v, j);
  return pr->objective(x);
}

}  // namespace

BlockErrors block_errors(const std::vector<double>& dem_angle_deg, const std::vector<double>& dem_speed,
                         const std::vector<double>& angle_deg, const std::vector<double>& speed, std::size_t begin,
                         std::size_t end) {
  BlockErrors e;
  double sa = 0, ss = 0, sd = 0;
  int na = 0, ns = 0, nd = 0;
  for (std::size_t j = begin; j < end; ++j) {
    if (std::isfinite(dem_angle_deg[j]) && std::isfinite(angle_deg[j])) {
      sa += (dem_angle_deg[j] - angle_deg[j]) * (dem_angle_deg[j] - angle_deg[j]), ++na;
    }
    if (std::isfinite(dem_speed[j]) && std::isfinite(speed[j])) ss += (dem_speed[j] - speed[j]) * (dem_speed[j] - speed[j]), ++ns;
    if (std::isfinite(dem_speed[j])) sd += dem_speed[j] * dem_speed[j], ++nd;
  }
  e.frames = static_cast<int>(end - begin);
  if (!na || !ns || !nd) return e;
  e.angle_rms_deg = std::sqrt(sa / na), e.speed_rms = std::sqrt(ss / ns), e.dem_speed_rms = std::sqrt(sd / nd);
  const double speed_scale = kSpeedTolerance * std::max(e.dem_speed_rms, kSpeedFloor);
  e.objective = std::pow(e.angle_rms_deg / kAngleTolerance, 2) + std::pow(e.speed_rms / speed_scale, 2);
  e.agrees = e.angle_rms_deg <= kAngleTolerance && e.speed_rms <= speed_scale;
  return e;
}

ClosureFit fit_closure_friction(const ClosureFitSettings& settings, const std::string& where,
                                const std::vector<double>& times, const std::vector<double>& dem_angle_deg,
                                const std::vector<double>& dem_speed, const BedFriction& a_priori,
                                const ClosureRun& run) {
  ClosureFit fit;
  fit.settings = settings;
  std::vector<std::string> names = settings.parameters;
  if (names.empty()) names = {"internal_friction_deg", "basal_friction_deg", "flowing_layer_diameters"};
  Problem pr;
  for (const std::string& n : names) {
    const auto& table = parameter_table();
    const auto it = std::find_if(table.begin(), table.end(), [&](const Parameter& p) { return n == p.name; });
    if (it == table.end()) {
      throw InputError(where + ": fit parameter '" + n + "' is not one of internal_friction_deg, basal_friction_deg, "
                       "flowing_layer_diameters, delta_mu, start_excess_deg");
    }
    if (std::find(pr.params.begin(), pr.params.end(), &*it) != pr.params.end()) {
      throw InputError(where + ": fit parameter '" + n + "' is listed twice");
    }
    pr.params.push_back(&*it);
  }
  for (const Parameter* p : pr.params) {
    if (std::string(p->name) == "flowing_layer_diameters" && !std::isfinite(a_priori.layer_depth)) {
      throw InputError(where + ": fit of flowing_layer_diameters needs a finite a-priori flowing layer (the plug, "
                       "l = infinity, is beyond its range: give flowing_layer_diameters in the scenario)");
    }
  }
  const std::size_t n = times.size();
  std::size_t split = 0;
  while (split < n && times[split] <= settings.train_until) ++split;
  if (split < 3 || n - split < 3) {
    throw InputError(where + ": fit.train_until = " + std::to_string(settings.train_until) + " s leaves " +
                     std::to_string(split) + " training and " + std::to_string(n - split) +
                     " test frames; each side needs at least 3 (frames from " + std::to_string(times.front()) + " to " +
                     std::to_string(times.back()) + " s)");
  }
  pr.base = a_priori, pr.run = &run, pr.dem_angle = &dem_angle_deg, pr.dem_speed = &dem_speed, pr.train_end = split;
  const std::size_t np = pr.params.size();
  fit.names = names;
  std::vector<double> x0(np);
  for (std::size_t j = 0; j < np; ++j) x0[j] = std::clamp(pr.params[j]->get(a_priori), pr.params[j]->lo, pr.params[j]->hi);

  // The a-priori closure on both blocks.
  {
    std::vector<double> a, u;
    run(a_priori, a, u);
    fit.a_priori_train = block_errors(dem_angle_deg, dem_speed, a, u, 0, split);
    fit.a_priori_test = block_errors(dem_angle_deg, dem_speed, a, u, split, n);
  }

  // 1. The grid (and the a-priori point): the objective has corners (yield thresholds), so a local
  // search alone can stop at the first plateau.
  std::vector<double> best = x0;
  double jbest = pr.objective(x0);
  std::vector<std::size_t> idx(np, 0);
  for (;;) {
    std::vector<double> x(np);
    for (std::size_t j = 0; j < np; ++j) x[j] = pr.params[j]->grid[idx[j]];
    const double jx = pr.objective(x);
    if (jx < jbest) jbest = jx, best = x;
    std::size_t j = 0;
    while (j < np && ++idx[j] == pr.params[j]->grid.size()) idx[j++] = 0;
    if (j == np) break;
  }

  // 2. Nelder–Mead from the best point (GSL nmsimplex2), restarted once from its own answer.
  for (int restart = 0; restart < 2; ++restart) {
    gsl_multimin_function fn{&gsl_objective, np, &pr};
    gsl_vector* x = gsl_vector_alloc(np);
    gsl_vector* step = gsl_vector_alloc(np);
    for (std::size_t j = 0; j < np; ++j) gsl_vector_set(x, j, best[j]), gsl_vector_set(step, j, pr.params[j]->step);
    gsl_multimin_fminimizer* m = gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, np);
    gsl_multimin_fminimizer_set(m, &fn, x, step);
    for (int it = 0; it < 400; ++it) {
      if (gsl_multimin_fminimizer_iterate(m)) break;
      if (gsl_multimin_test_size(gsl_multimin_fminimizer_size(m), 1e-4) == GSL_SUCCESS) break;
    }
    if (m->fval < jbest) {
      jbest = m->fval;
      for (std::size_t j = 0; j < np; ++j) best[j] = std::clamp(gsl_vector_get(m->x, j), pr.params[j]->lo, pr.params[j]->hi);
    }
    gsl_multimin_fminimizer_free(m);
    gsl_vector_free(x);
    gsl_vector_free(step);
  }

  // 3. Sensitivity: each parameter alone (the others at the fit) over the range where the training
  // objective rises by at most kRangeRise: the errors grow by at most half the bar in quadrature.
  fit.lower.resize(np), fit.upper.resize(np);
  // The edge is bracketed by steps that double from p.scan, then bisected to p.scan.
  for (std::size_t j = 0; j < np; ++j) {
    const Parameter& p = *pr.params[j];
    for (int side = -1; side <= 1; side += 2) {
      std::vector<double> x = best;
      auto within = [&](double v) {
        x[j] = v;
        return pr.objective(x) <= jbest + kRangeRise;
      };
      const double bound = side < 0 ? p.lo : p.hi;
      double good = best[j], bad = NAN;
      for (double step = p.scan;; step *= 2) {
        const double next = side < 0 ? std::max(good - step, bound) : std::min(good + step, bound);
        if (!within(next)) {
          bad = next;
          break;
        }
        good = next;
        if (next == bound) break;
      }
      while (std::isfinite(bad) && std::fabs(bad - good) > p.scan) {
        const double mid = 0.5 * (good + bad);
        (within(mid) ? good : bad) = mid;
      }
      (side < 0 ? fit.lower[j] : fit.upper[j]) = shown(p, good);
    }
  }

  // The fitted closure on both blocks.
  const BedFriction fitted = pr.friction(best);
  run(fitted, fit.angle_deg, fit.speed);
  fit.fitted_train = block_errors(dem_angle_deg, dem_speed, fit.angle_deg, fit.speed, 0, split);
  fit.fitted_test = block_errors(dem_angle_deg, dem_speed, fit.angle_deg, fit.speed, split, n);
  for (std::size_t j = 0; j < np; ++j) {
    fit.a_priori.push_back(shown(*pr.params[j], pr.params[j]->get(a_priori)));
    fit.fitted.push_back(shown(*pr.params[j], best[j]));
  }
  fit.evaluations = pr.evaluations;
  return fit;
}

}  // namespace grainscale::studies
