#include "studies/trial_sweep_run.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "continuum/observation.hpp"
#include "studies/hold_measures.hpp"
#include "studies/hold_run.hpp"
#include "studies/loop_motion.hpp"

namespace grainscale::studies {

namespace {

struct PreparedCase {
  HoldSettings settings;
  double kappa = 0, delta = 0;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

TrialCaseResult run_case(const PreparedCase& p, double end_length) {
  TrialCaseResult r;
  const auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<HoldModel> model;
  const HoldResult h = run_hold(p.settings, model, nullptr);
  const continuum::Grid& g = model->model().grid();
  const std::vector<double>& c = model->chaff();
  const continuum::SurfaceCoverage obs(p.kappa, p.delta);
  r.profile = obs.coverage(g, c);
  for (int i = 0; i < g.nx(); ++i) r.x.push_back(g.x_centre(i));
  const double L = g.length(), e = std::min(end_length, 0.5 * L);
  r.coverage.left = zone_mean(r.x, r.profile, 0, e);
  r.coverage.right = zone_mean(r.x, r.profile, L - e, L);
  r.coverage.centre = zone_mean(r.x, r.profile, 0.5 * (L - e), 0.5 * (L + e));
  r.ratio = 0.5 * (r.coverage.left + r.coverage.right) / r.coverage.centre;
  const auto [sl, sr] = end_top_fractions(g, c, p.settings.top_layer, p.settings.end_zone);
  r.share_left = sl;
  r.share_right = sr;
  r.chaff_change = h.chaff_initial > 0 ? (h.chaff_final - h.chaff_initial) / h.chaff_initial : 0;
  r.c_min = h.c_min;
  r.c_max = h.c_max;
  r.resolved_cycles = h.resolved_chunks;
  r.closure_steps = h.closure_steps;
  r.chaff_steps = h.chaff_steps;
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace

double zone_mean(const std::vector<double>& x, const std::vector<double>& values, double a, double b) {
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] >= a && x[i] <= b && std::isfinite(values[i])) sum += values[i], ++n;
  }
  return n ? sum / n : NAN;
}

TrialSweepResult run_trial_sweep(const TrialPlanSettings& s, int threads,
                                 const std::function<void(const std::string&)>& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t nd = s.designs.size(), nv = s.variants.size(), n = nd * nv;
  // Every case's settings prepared here, serially: private copies of the YAML term nodes and motion.
  std::vector<PreparedCase> cases(n);
  for (std::size_t d = 0; d < nd; ++d) {
    const TrialDesign& design = s.designs[d];
    for (std::size_t v = 0; v < nv; ++v) {
      PreparedCase& p = cases[d * nv + v];
      p.settings = hold_settings_for(s.base, motion_of(s, design), design, s.duration, s.resolve, s.average_cycles,
                                     s.end_length);
      MotionFacts facts = cycle_facts(*p.settings.motion);
      facts.axis_x = p.settings.pivot_x;
      facts.axis_z = p.settings.pivot_z;
      p.kappa = s.kappa;
      p.delta = s.delta;
      apply_variant(s.variants[v], p.settings, facts, p.kappa, p.delta);
    }
  }
  TrialSweepResult out;
  out.threads = threads > 0 ? threads : omp_get_max_threads();
  std::vector<TrialCaseResult> flat(n);
  std::size_t done = 0;
  if (log) {
    log("sweep: " + std::to_string(nd) + " designs x " + std::to_string(nv) + " variants = " + std::to_string(n) +
        " hold predictions of " + fmt(s.duration) + " s each, on " + std::to_string(out.threads) + " threads");
  }
  const std::size_t every = std::max<std::size_t>(1, n / 20);
#pragma omp parallel for schedule(dynamic, 1) num_threads(out.threads)
  for (std::size_t k = 0; k < n; ++k) {
    TrialCaseResult r;
    try {
      r = run_case(cases[k], s.end_length);
    } catch (const std::exception& e) {
      r = TrialCaseResult{};
      r.coverage = {NAN, NAN, NAN};
      r.ratio = r.share_left = r.share_right = NAN;
      r.error = e.what();
    }
    flat[k] = std::move(r);
#pragma omp critical(trial_sweep_progress)
    {
      ++done;
      if (log && (done % every == 0 || done == n || !flat[k].error.empty())) {
        const double el = seconds_since(t0);
        const double eta = el / done * (n - done);
        const TrialDesign& d = s.designs[k / nv];
        log("case " + std::to_string(done) + "/" + std::to_string(n) + " done (" + d.label() + ", variant " +
            s.variants[k % nv].name + (flat[k].error.empty() ? "" : ": FAILED: " + flat[k].error) + "); elapsed " +
            fmt(el) + " s, ETA " + fmt(eta) + " s");
      }
    }
  }
  out.cases.assign(nd, std::vector<TrialCaseResult>(nv));
  for (std::size_t k = 0; k < n; ++k) out.cases[k / nv][k % nv] = std::move(flat[k]);
  out.wall_seconds = seconds_since(t0);
  return out;
}

}  // namespace grainscale::studies
