#include "studies/loop_study_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "continuum/settings.hpp"
#include "dem/atomic_file.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string g(double v, int digits = 4) {
  if (!std::isfinite(v)) return "-";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string figure(const std::string& out, const std::string& rel, const std::string& caption) {
  if (!fs::exists(fs::path(out) / rel)) return "";
  return "![" + caption + "](" + rel + ")\n\n*" + caption + "*\n\n";
}

std::string verdict(const Diagnosis& d) { return !d.tested ? "untested (too few points)" : d.white ? "white" : "structured"; }

/// The candidate's own (not base) parameters as "name = v ± se".
std::string strength(const Evaluation& e, std::size_t base_parameters) {
  std::string t;
  for (std::size_t p = base_parameters; p < e.parameters.size(); ++p) {
    t += (t.empty() ? "" : "; ") + ("`" + e.parameters[p] + "` = " + g(e.values[p]) + " ± " + g(e.standard_errors[p]));
  }
  return t.empty() ? "-" : t;
}

}  // namespace

std::string write_loop_study_report(const LoopStudySettings& s, const LoopStudyResults& res, const std::string& out) {
  const LoopResult& r = res.loop;
  const LoopSettings& ls = s.loop;
  const FitCommandSettings& fit = ls.fit;
  const continuum::Model probe = continuum::build_model(fit.model);
  const continuum::Grid& grid = probe.grid();
  const std::size_t kb = r.base.parameters.size();
  const Evaluation* chosen = r.chosen >= 0 ? &r.candidates[r.chosen] : nullptr;
  const Evaluation& after = chosen ? *chosen : r.base;
  std::ostringstream m;

  m << "# " << s.title << "\n\n";
  if (!s.description.empty()) m << s.description << "\n\n";
  m << "Study `" << s.name << "` (kind `loop`), run with `grainscale study " << s.source_file << "`: `grainscale loop "
    << s.loop_file << "` (docs/loop.md) on the data below, into `loop/` (its own report with every table: "
    << "`loop/report.md`; numbers: `loop/loop.yaml`). Inputs as run: `inputs/`; log: `log.txt`.\n\n";

  m << "## What was run\n\n| step | result | wall clock |\n|---|---|---|\n"
    << "| 1. base fit (" << kb << " parameter" << (kb == 1 ? "" : "s") << ") and its cross-validation | chi2 "
    << g(r.base.chi2) << " for " << r.base.n << " observations, CV error " << g(r.base.cv_error) << " | "
    << g(r.base.seconds, 3) << " s |\n";
  double cand_seconds = 0;
  for (const auto& e : r.candidates) cand_seconds += e.seconds;
  m << "| 2. diagnosis of the base residual | " << verdict(r.diagnosis_before) << " | - |\n"
    << "| 3. " << r.candidates.size() << " candidate effects fitted and cross-validated | "
    << std::count_if(r.candidates.begin(), r.candidates.end(), [](const Evaluation& e) { return e.ok; }) << " fitted | "
    << g(cand_seconds, 3) << " s |\n"
    << "| 4. decision | " << (chosen ? "added `" + chosen->name + "`" : std::string("nothing added")) << " | - |\n"
    << "| total (with figures and files) | | " << g(res.wall_seconds, 3) << " s |\n\n";

  std::vector<std::string> warnings;
  if (!r.diagnosis_before.tested) warnings.push_back("the base residual has too few points in series for the whiteness tests: untested, not white");
  if (!std::isfinite(r.base.cv_error)) {
    warnings.push_back("the base model has no cross-validated error (" + std::to_string(r.base.cv_folds) +
                       " usable folds): no added effect can be justified by these data");
  }
  for (const auto& w : r.base.warnings) warnings.push_back("base fit: " + w);
  for (const auto& e : r.candidates) {
    if (!e.ok) warnings.push_back(e.name + " could not be fitted: " + e.error);
  }
  if (!warnings.empty()) {
    m << "## Warnings\n\n";
    for (const auto& w : warnings) m << "- " << w << "\n";
    m << "\n";
  }

  // 1. Data.
  m << "## 1. The data and where they come from\n\n";
  if (!fit.data.coverage.empty()) m << "Top-view coverage: `" << fit.data.coverage << "`. ";
  if (!fit.data.fields.empty()) m << "Concentration fields: `" << fit.data.fields << "`. ";
  m << r.data.fields.size() << " field and " << r.data.coverage.size() << " coverage observations at "
    << r.data.times.size() << " time" << (r.data.times.size() == 1 ? "" : "s") << " (after t0 = " << g(fit.t0) << " s), "
    << (r.data.sigma_known ? "each with its measurement sigma" : "without sigma (the noise is estimated from the scatter)")
    << ". Model grid: " << grid.nx() << " x " << grid.nz() << " cells over " << g(grid.length(), 3)
    << " m; flow `" << fit.model.flow.type << "` (`" << fit.model_file << "`).\n\n";
  if (!s.provenance.empty()) {
    m << "Provenance: `inputs/" << fs::path(s.provenance).filename().string() << "` (copied from `" << s.provenance
      << "`): the source, what it says in its own words, and why each sigma is what it is.\n\n";
  }
  double wmax = 0;
  for (const auto& o : r.data.coverage) wmax = std::max(wmax, 1 / (o.sigma * o.sigma));
  for (const auto& o : r.data.fields) wmax = std::max(wmax, 1 / (o.sigma * o.sigma));
  int light = 0;
  if (r.data.coverage.size() + r.data.fields.size() <= 24) {
    m << "| t (s) | kind | x (m, column centre) | value | sigma | weight (of the largest) | model before | model after |\n"
      << "|---|---|---|---|---|---|---|---|\n";
    auto row = [&](const Observation& o, bool cov) {
      const double w = 1 / (o.sigma * o.sigma) / wmax;
      light += w < 0.01;
      const int col = cov ? static_cast<int>(o.index) : static_cast<int>(o.index) % grid.nx();
      const auto& pb = cov ? r.base.prediction.coverage : r.base.prediction.fields;
      const auto& pa = cov ? after.prediction.coverage : after.prediction.fields;
      const double before = o.time < pb.size() ? pb[o.time][o.index] : NAN;
      const double aft = o.time < pa.size() ? pa[o.time][o.index] : NAN;
      m << "| " << g(r.data.times[o.time]) << " | " << (cov ? "coverage" : "c") << " | " << g(grid.x_centre(col), 3) << " | "
        << g(o.value, 3) << " | " << g(o.sigma, 3) << " | " << g(100 * w, 3) << " % | " << g(before, 3) << " | " << g(aft, 3)
        << " |\n";
    };
    for (const auto& o : r.data.fields) row(o, false);
    for (const auto& o : r.data.coverage) row(o, true);
    m << "\n";
  } else {
    for (const auto& o : r.data.fields) light += 1 / (o.sigma * o.sigma) / wmax < 0.01;
    for (const auto& o : r.data.coverage) light += 1 / (o.sigma * o.sigma) / wmax < 0.01;
  }
  if (!s.caveats.empty() || light > 0) {
    m << "Caveats:\n\n";
    for (const auto& c : s.caveats) m << "- " << c << "\n";
    if (light > 0) {
      m << "- " << light << " observation" << (light == 1 ? " carries" : "s carry")
        << " less than 1 % of the largest weight (a large sigma: data the source does not vouch for); "
        << (light == 1 ? "it shows" : "they show") << " in the figures but cannot pull the fit.\n";
    }
    m << "\n";
  }
  if (ls.motion) {
    m << "Motion (from `" << ls.scenario_file << "`, wall `" << ls.motion->container << "`): period "
      << g(ls.motion->period) << " s, peak tilt " << g(ls.motion->peak_angle_deg, 3) << " deg, <omega^2> = "
      << g(ls.motion->omega2_mean) << " 1/s^2, <alpha^2> = " << g(ls.motion->alpha2_mean) << " 1/s^4, paused " << g(100 * ls.motion->pause_fraction, 3)
      << " % of the cycle, rotation axis at x = " << g(ls.motion->axis_x) << " m, z = " << g(ls.motion->axis_z)
      << " m in the container frame; it sets the lever-arm and pause candidates.\n\n";
  }

  // 2. Base fit.
  m << "## 2. The base model's fit\n\n| parameter | value | standard error |\n|---|---|---|\n";
  for (std::size_t j = 0; j < kb; ++j) {
    m << "| `" << r.base.parameters[j] << "` | " << g(r.base.values[j]) << " | " << g(r.base.standard_errors[j]) << " |\n";
  }
  const int dof = std::max(1, r.base.n - r.base.k);
  m << "\nchi2 = " << g(r.base.chi2) << " for " << r.base.n << " observations and " << r.base.k << " parameter"
    << (r.base.k == 1 ? "" : "s") << " (chi2/dof = " << g(r.base.chi2 / dof) << "; about 1 if the model fits within "
    << "the data's sigma), " << r.base.fit.iterations << " iterations, " << (r.base.fit.converged ? "converged" : "**not converged**")
    << ". RMSE " << (r.data.coverage.empty() ? "fields " + g(r.base.rmse_fields) : "coverage " + g(r.base.rmse_coverage))
    << ", max error " << (r.data.coverage.empty() ? g(r.base.max_fields) : g(r.base.max_coverage)) << ".\n\n"
    << figure(out, "loop/before_coverage.png", "base model: coverage, data and model")
    << figure(out, "loop/before_fields_last.png", "base model: fields at the last time, data, model and residual")
    << figure(out, "loop/before_coverage_residual.png", "base model: coverage residual");

  // 3. Diagnosis.
  const Diagnosis& d = r.diagnosis_before;
  m << "## 3. Diagnosis of the residual\n\n"
    << "Residual r = (model - data)/sigma of the base fit: RMS " << g(d.rms) << " over " << d.points
    << " observations; whiteness: **" << d.verdict << "**.\n\n| split | value |\n|---|---|\n"
    << "| symmetric / antisymmetric about the centre (energy fractions, " << d.mirrored_pairs << " mirrored pairs) | "
    << (d.mirrored_pairs ? g(d.symmetric_energy, 3) + " / " + g(d.antisymmetric_energy, 3) : std::string("no mirrored pairs"))
    << " |\n"
    << "| harmonics of the motion | "
    << (d.harmonics_resolved ? "mean " + g(d.mean_energy, 3) + ", 1st " + g(d.first_harmonic, 3) + ", 2nd " +
                                   g(d.second_harmonic, 3) + ", rest " + g(d.rest_energy, 3)
                             : "not resolved: " + d.harmonics_note)
    << " |\n| correlation of r with the model's c | " << g(d.correlation_with_c, 3) << " |\n";
  for (const auto& reg : d.regions) {
    if (reg.count) m << "| " << reg.name << " (" << reg.count << ") | RMS " << g(reg.rms, 3) << ", mean " << g(reg.mean, 3) << " |\n";
  }
  m << "\nA positive mean r is a model above the data. Full tables (whiteness tests): `loop/report.md`.\n\n"
    << figure(out, "loop/before_regions.png", "RMS residual by region (base)")
    << figure(out, "loop/before_residual_vs_c.png", "residual against the model's c (base)")
    << figure(out, "loop/before_autocorrelation.png", "autocorrelation of the residual (base)")
    << figure(out, "loop/before_harmonics.png", "residual energy by harmonic of the motion (base)");

  // 4. Ranking.
  m << "## 4. Candidate effects, ranked\n\n"
    << "Each candidate effect (docs/loop.md, the library) is fitted together with the base parameters and ranked by "
    << "blocked cross-validation (" << ls.cv.blocks << " " << r.base.cv_by << " blocks, each held out in turn; "
    << "'-' where a fold leaves too few observations for the parameters). dBIC < 0 favours the candidate on all "
    << "the data.\n\n| rank | candidate | fitted strength ± SE | CV error | dAIC | dBIC | notes |\n|---|---|---|---|---|---|---|\n"
    << "| 0 | base | - | " << g(r.base.cv_error) << " | 0 | 0 | |\n";
  for (std::size_t j = 0; j < r.candidates.size(); ++j) {
    const Evaluation& e = r.candidates[j];
    if (!e.ok) {
      m << "| " << j + 1 << " | " << e.name << " | - | - | - | - | not fitted: " << e.error << " |\n";
      continue;
    }
    std::string notes;
    for (const auto& w : e.warnings) notes += (notes.empty() ? "" : "; ") + w;
    m << "| " << j + 1 << " | " << e.name << " | " << strength(e, kb) << " | " << g(e.cv_error) << " | "
      << g(e.aic - r.base.aic, 3) << " | " << g(e.bic - r.base.bic, 3) << " | " << notes << " |\n";
  }
  m << "\n" << figure(out, "loop/ranking.png", "cross-validated error of the base (0) and the candidates in rank order");

  // 5. Decision.
  m << "## 5. The effect added\n\n";
  if (chosen) {
    m << "**Added: `" << chosen->name << "`**, " << strength(*chosen, kb) << ". Why: " << r.reason << ".\n\n";
  } else {
    m << "**Nothing added.** Why: " << r.reason << ".\n\n";
    // The candidate the full-data fit favours most, for the reader's benefit.
    const Evaluation* best = nullptr;
    for (const auto& e : r.candidates)
      if (e.ok && (!best || e.bic < best->bic)) best = &e;
    if (best && best->bic < r.base.bic) {
      m << "On all the data (no cross-validation) `" << best->name << "` fits best: BIC lower by "
        << g(r.base.bic - best->bic, 3) << ", " << strength(*best, kb)
        << ". That points at the effect but does not establish it: without held-out data it may fit the noise.\n\n";
    }
  }
  m << "Verdict: " << (chosen ? "the data justify adding `" + chosen->name + "`." : std::string("the data justify no added effect."))
    << " The residual after is " << verdict(r.diagnosis_after) << ".\n\n";

  // 6. Error before and after.
  m << "## 6. Error before and after\n\n| | before (base) | after" << (chosen ? " (base + " + chosen->name + ")" : " (nothing added: the base)")
    << " |\n|---|---|---|\n"
    << "| RMS of (model - data)/sigma | " << g(r.base.rms) << " | " << g(after.rms) << " |\n"
    << "| cross-validated error (held-out RMS r) | " << g(r.base.cv_error) << " | " << g(after.cv_error) << " |\n"
    << "| CV error beyond the noise, sqrt(max(cv^2 - 1, 0)) | " << g(r.base.cv_model_error) << " | " << g(after.cv_model_error) << " |\n";
  if (!r.data.coverage.empty()) {
    m << "| RMSE coverage | " << g(r.base.rmse_coverage) << " | " << g(after.rmse_coverage) << " |\n"
      << "| max error coverage | " << g(r.base.max_coverage) << " | " << g(after.max_coverage) << " |\n"
      << "| CV RMSE coverage | " << g(r.base.cv_rmse_coverage) << " | " << g(after.cv_rmse_coverage) << " |\n";
  }
  if (!r.data.fields.empty()) {
    m << "| RMSE fields (c) | " << g(r.base.rmse_fields) << " | " << g(after.rmse_fields) << " |\n"
      << "| max error fields | " << g(r.base.max_fields) << " | " << g(after.max_fields) << " |\n"
      << "| CV RMSE fields | " << g(r.base.cv_rmse_fields) << " | " << g(after.cv_rmse_fields) << " |\n";
  }
  m << "| residual | " << verdict(r.diagnosis_before) << " | " << verdict(r.diagnosis_after) << " |\n\n";
  if (chosen) {
    m << figure(out, "loop/after_coverage.png", "after: coverage, data and model")
      << figure(out, "loop/after_fields_last.png", "after: fields at the last time")
      << figure(out, "loop/after_coverage_residual.png", "after: coverage residual")
      << figure(out, "loop/after_regions.png", "after: RMS residual by region");
  }
  m << figure(out, "loop/before_residuals.png", "histogram of the base residual");

  // Limits, from the numbers.
  m << "## Limits\n\n";
  const int n = r.base.n, times = static_cast<int>(r.data.times.size());
  m << "- **" << n << " observation" << (n == 1 ? "" : "s") << " at " << times << " time" << (times == 1 ? "" : "s")
    << "** for " << r.base.k << " base parameter" << (r.base.k == 1 ? "" : "s") << " and one more per candidate";
  if (light > 0) m << " (" << light << " of them with negligible weight)";
  m << ". ";
  if (times < 2) {
    m << "One measured profile says where chaff is at one moment, not how it got there: build-up over time, the "
         "harmonics of the motion and time-blocked cross-validation are out of reach.\n";
  } else {
    m << "\n";
  }
  const bool any_cv = std::any_of(r.candidates.begin(), r.candidates.end(),
                                  [](const Evaluation& e) { return e.ok && std::isfinite(e.cv_error); });
  if (!std::isfinite(r.base.cv_error) || !any_cv) {
    m << "- **No candidate can be cross-validated**: holding out one of the " << ls.cv.blocks << " " << r.base.cv_by
      << " blocks leaves too few observations to refit " << (std::isfinite(r.base.cv_error) ? "base + candidate" : "even the base")
      << " and predict it; an effect that lowers BIC on all the data cannot be told from one that fits the noise.\n";
  }
  if (!d.tested) m << "- **The residual's whiteness is untested** (too few points in a series): 'no structure left' cannot be claimed.\n";
  m << "- **The model's flow is `" << fit.model.flow.type << "`**";
  if (fit.model.flow.type == "uniform_shear" || fit.model.flow.type == "none") {
    m << ", a stand-in, not the measured or simulated flow of the experiment: any residual it leaves may be the flow's, "
         "not a missing chaff effect.\n";
  } else {
    m << ".\n";
  }
  m << "- **The candidate library is finite** (docs/loop.md): an effect outside it shows only as a residual no "
       "candidate explains. The loop adds at most one effect per run.\n"
    << "- What would help: coverage profiles at several times, or coarse-grained DEM fields of the same box "
       "(`data.fields: fields.h5`), so that cross-validation can hold out whole times.\n";

  const std::string path = (fs::path(out) / "report.md").string();
  dem::write_file_atomically(path, m.str());
  return path;
}

}  // namespace grainscale::studies
