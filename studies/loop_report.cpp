#include "studies/loop_report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "dem/atomic_file.hpp"
#include "grainscale_version.hpp"
#include "studies/fit_plots.hpp"
#include "studies/loop_command.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string g(double v) {
  if (std::isnan(v)) return ".nan";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string s4(double v) {
  if (std::isnan(v)) return "-";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string verdict(const Diagnosis& d) { return !d.tested ? "untested" : d.white ? "white" : "structured"; }

void yaml_evaluation(std::ostringstream& y, const Evaluation& e, const std::string& indent) {
  y << indent << "ok: " << (e.ok ? "true" : "false") << "\n";
  if (!e.ok) {
    y << indent << "error: " << quoted(e.error) << "\n";
    return;
  }
  y << indent << "parameters:\n";
  for (std::size_t j = 0; j < e.parameters.size(); ++j) {
    y << indent << "  " << e.parameters[j] << ": {value: " << g(e.values[j]) << ", standard_error: " << g(e.standard_errors[j])
      << "}\n";
  }
  y << indent << "chi2: " << g(e.chi2) << "\n"
    << indent << "observations: " << e.n << "\n"
    << indent << "aic: " << g(e.aic) << "\n"
    << indent << "bic: " << g(e.bic) << "\n"
    << indent << "rms_normalised: " << g(e.rms) << "\n"
    << indent << "rmse_fields: " << g(e.rmse_fields) << "\n"
    << indent << "max_error_fields: " << g(e.max_fields) << "\n"
    << indent << "rmse_coverage: " << g(e.rmse_coverage) << "\n"
    << indent << "max_error_coverage: " << g(e.max_coverage) << "\n"
    << indent << "cv: {by: " << e.cv_by << ", folds: " << e.cv_folds << ", points: " << e.cv_points
    << ", error: " << g(e.cv_error) << ", model_error: " << g(e.cv_model_error) << ", rmse_fields: " << g(e.cv_rmse_fields) << ", rmse_coverage: " << g(e.cv_rmse_coverage)
    << "}\n"
    << indent << "converged: " << (e.fit.converged ? "true" : "false") << "\n"
    << indent << "iterations: " << e.fit.iterations << "\n"
    << indent << "seconds: " << g(e.seconds) << "\n"
    << indent << "warnings: [";
  for (std::size_t j = 0; j < e.warnings.size(); ++j) y << (j ? ", " : "") << quoted(e.warnings[j]);
  y << "]\n";
}

void yaml_diagnosis(std::ostringstream& y, const Diagnosis& d) {
  y << "  points: " << d.points << "\n  rms_normalised: " << g(d.rms) << "\n"
    << "  symmetry: {pairs: " << d.mirrored_pairs << ", symmetric: " << g(d.symmetric_energy)
    << ", antisymmetric: " << g(d.antisymmetric_energy) << "}   # fractions of the paired residual energy\n"
    << "  regions:\n";
  for (const auto& r : d.regions) {
    y << "    - {name: " << quoted(r.name) << ", count: " << r.count << ", rms: " << g(r.rms) << ", mean: " << g(r.mean) << "}\n";
  }
  y << "  harmonics: {resolved: " << (d.harmonics_resolved ? "true" : "false") << ", note: " << quoted(d.harmonics_note)
    << ", locations: " << d.harmonic_locations << ", mean: " << g(d.mean_energy) << ", first: " << g(d.first_harmonic)
    << ", second: " << g(d.second_harmonic) << ", rest: " << g(d.rest_energy) << "}\n"
    << "  correlation_with_model_c: " << g(d.correlation_with_c) << "\n  model_c_bins:\n";
  for (std::size_t b = 0; b < d.c_bin_centre.size(); ++b) {
    y << "    - {c: " << g(d.c_bin_centre[b]) << ", mean_r: " << g(d.c_bin_mean_r[b]) << ", count: " << d.c_bin_count[b] << "}\n";
  }
  y << "  whiteness:\n";
  for (const auto& t : d.tests) {
    y << "    - {order: " << t.order << ", series: " << t.series << ", points: " << t.points << ", lags: " << t.lags
      << ", portmanteau_q: " << g(t.q) << ", portmanteau_p: " << g(t.q_p) << ", runs: " << g(t.runs)
      << ", runs_expected: " << g(t.runs_expected) << ", runs_p: " << g(t.runs_p) << "}\n";
  }
  y << "  tested: " << (d.tested ? "true" : "false") << "\n  white: " << (d.white ? "true" : "false") << "\n  verdict: " << quoted(d.verdict) << "\n";
}

void md_diagnosis(std::ostringstream& m, const Diagnosis& d) {
  m << "RMS of (model - data)/sigma: **" << s4(d.rms) << "** over " << d.points << " observations. Whiteness: **"
    << d.verdict << "**.\n\n"
    << "| split | value |\n|---|---|\n"
    << "| symmetric / antisymmetric about the centre (energy fractions, " << d.mirrored_pairs << " mirrored pairs) | "
    << s4(d.symmetric_energy) << " / " << s4(d.antisymmetric_energy) << " |\n";
  if (d.harmonics_resolved) {
    m << "| cycle mean / 1st / 2nd harmonic / rest (energy fractions, " << d.harmonic_locations << " locations) | "
      << s4(d.mean_energy) << " / " << s4(d.first_harmonic) << " / " << s4(d.second_harmonic) << " / " << s4(d.rest_energy) << " |\n";
  } else {
    m << "| harmonics of the motion | not resolved: " << d.harmonics_note << " |\n";
  }
  m << "| correlation of r with the model's c | " << s4(d.correlation_with_c) << " |\n\n"
    << "| region | observations | RMS r | mean r |\n|---|---|---|---|\n";
  for (const auto& r : d.regions) m << "| " << r.name << " | " << r.count << " | " << s4(r.rms) << " | " << s4(r.mean) << " |\n";
  m << "\n| ordered in | series | points | lags | portmanteau Q | p | runs (expected) | p |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& t : d.tests) {
    m << "| " << t.order << " | " << t.series << " | " << t.points << " | " << t.lags << " | " << s4(t.q) << " | " << s4(t.q_p)
      << " | " << s4(t.runs) << " (" << s4(t.runs_expected) << ") | " << s4(t.runs_p) << " |\n";
  }
  m << "\n";
}

/// Figures of one diagnosis, prefixed (before_/after_).
void diagnosis_figures(const Diagnosis& d, const std::string& folder, const std::string& prefix, std::vector<std::string>& out) {
  auto save = [&](const Image& img, const std::string& name) {
    img.write_png((fs::path(folder) / (prefix + name)).string());
    out.push_back(prefix + name);
  };
  try {
    BarChart regions;
    regions.axes = {.title = "RMS residual by region (" + prefix.substr(0, prefix.size() - 1) + ")",
                    .x_label = "1 surface  2 bulk  3 coverage  4 near walls  5 interior",
                    .y_label = "RMS (model - data)/sigma"};
    for (int j = 0; j <= 5; ++j) regions.edges.push_back(0.5 + j);
    BarSeries rms{"RMS", {}}, mean{"mean", {}};
    for (const auto& r : d.regions) {
      rms.values.push_back(r.count ? r.rms : NAN);
      mean.values.push_back(r.count ? r.mean : NAN);
    }
    regions.series = {rms, mean};
    save(draw(regions), "regions.png");
  } catch (const std::exception& e) {
    std::cout << "no plot " << prefix << "regions.png: " << e.what() << "\n";
  }
  try {
    LinePlot c;
    c.axes = {.title = "Residual against the model's c", .x_label = "model c (bin mean)", .y_label = "mean (model - data)/sigma"};
    c.series.push_back({"binned mean", d.c_bin_centre, d.c_bin_mean_r, LineStyle::solid, Marker::circle});
    if (!d.c_bin_centre.empty()) c.series.push_back({"0", {d.c_bin_centre.front(), d.c_bin_centre.back()}, {0, 0}, LineStyle::dashed});
    save(draw(c), "residual_vs_c.png");
  } catch (const std::exception& e) {
    std::cout << "no plot " << prefix << "residual_vs_c.png: " << e.what() << "\n";
  }
  try {
    LinePlot a;
    a.axes = {.title = "Autocorrelation of the residual", .x_label = "lag", .y_label = "autocorrelation"};
    for (const auto& t : d.tests) {
      std::vector<double> lags, band_hi, band_lo;
      for (std::size_t k = 0; k < t.autocorrelation.size(); ++k) {
        lags.push_back(k + 1.0);
        band_hi.push_back(2 / std::sqrt(static_cast<double>(t.pairs[k])));
        band_lo.push_back(-band_hi.back());
      }
      a.series.push_back({"ordered in " + t.order, lags, t.autocorrelation, LineStyle::solid, Marker::circle});
      a.series.push_back({"+-2/sqrt(N), " + t.order, lags, band_hi, LineStyle::dashed});
      a.series.push_back({"", lags, band_lo, LineStyle::dashed});
    }
    save(draw(a), "autocorrelation.png");
  } catch (const std::exception& e) {
    std::cout << "no plot " << prefix << "autocorrelation.png: " << e.what() << "\n";
  }
  if (d.harmonics_resolved) {
    BarChart h;
    h.axes = {.title = "Residual energy by harmonic of the motion", .x_label = "0 cycle mean  1 first  2 second  3 rest",
              .y_label = "fraction of energy"};
    h.edges = {-0.5, 0.5, 1.5, 2.5, 3.5};
    h.series = {{"fraction", {d.mean_energy, d.first_harmonic, d.second_harmonic, d.rest_energy}}};
    save(draw(h), "harmonics.png");
  }
}

void fit_figures(const continuum::Grid& grid, const Observations& data, const Prediction& p, const std::string& folder,
                 const std::string& prefix, std::vector<std::string>& out) {
  auto save = [&](const Image& img, const std::string& name) {
    img.write_png((fs::path(folder) / (prefix + name)).string());
    out.push_back(prefix + name);
  };
  try {
    if (!data.fields.empty()) save(field_comparison(grid, data, p, field_times(data).back()), "fields_last.png");
    if (!data.coverage.empty()) {
      save(draw(coverage_comparison(grid, data, p)), "coverage.png");
      save(draw(coverage_residuals(grid, data, p)), "coverage_residual.png");
    }
    save(draw(residual_histogram(observation_residuals(p, data))), "residuals.png");
  } catch (const std::exception& e) {
    std::cout << "no plot " << prefix << "...: " << e.what() << "\n";
  }
}

/// residuals.csv: every observation with the base's and the chosen model's prediction and r = (model
/// − data) / sigma, so a user can look at the residual any way the diagnosis does not (by time, by
/// cell). Fields first (x and z of the cell's centre), then coverage (z empty).
std::string residuals_csv(const continuum::Grid& grid, const LoopResult& r, const Evaluation* chosen) {
  std::ostringstream out;
  out.precision(10);
  out << "kind,t_s,x_m,z_m,data,sigma,model_before,r_before,model_after,r_after\n";
  auto row = [&](const char* kind, const Observation& o, double z, double before, double after) {
    const int i = kind[0] == 'f' ? static_cast<int>(o.index) / grid.nz() : static_cast<int>(o.index);
    out << kind << ',' << r.data.times[o.time] << ',' << grid.x_centre(i) << ',';
    if (!std::isnan(z)) out << z;
    out << ',' << o.value << ',' << o.sigma << ',' << before << ',' << (before - o.value) / o.sigma << ',';
    if (chosen) out << after << ',' << (after - o.value) / o.sigma;
    else out << ',';
    out << '\n';
  };
  for (const Observation& o : r.data.fields) {
    const int i = static_cast<int>(o.index) / grid.nz(), k = static_cast<int>(o.index) % grid.nz();
    row("field", o, grid.z_centre(i, k), r.base.prediction.fields[o.time][o.index],
        chosen ? chosen->prediction.fields[o.time][o.index] : NAN);
  }
  for (const Observation& o : r.data.coverage) {
    row("coverage", o, NAN, r.base.prediction.coverage[o.time][o.index], chosen ? chosen->prediction.coverage[o.time][o.index] : NAN);
  }
  return out.str();
}

}  // namespace

std::vector<std::string> write_loop_outputs(const LoopSettings& s, const FitCommandSettings& fit, const continuum::Grid& grid,
                                            const LoopResult& r) {
  const std::string folder = s.output_folder;
  std::vector<std::string> figures;
  fit_figures(grid, r.data, r.base.prediction, folder, "before_", figures);
  diagnosis_figures(r.diagnosis_before, folder, "before_", figures);
  const Evaluation* chosen = r.chosen >= 0 ? &r.candidates[r.chosen] : nullptr;
  if (chosen) {
    fit_figures(grid, r.data, chosen->prediction, folder, "after_", figures);
    diagnosis_figures(r.diagnosis_after, folder, "after_", figures);
  }
  {
    BarChart rank;
    rank.axes = {.title = "Cross-validated error: base (0) and candidates (1, 2, ... as ranked)", .x_label = "rank",
                 .y_label = "CV error, RMS of held-out (model - data)/sigma"};
    rank.edges.push_back(-0.5);
    BarSeries cv{"CV error", {r.base.cv_error}};
    for (std::size_t j = 0; j < r.candidates.size(); ++j) cv.values.push_back(r.candidates[j].ok ? r.candidates[j].cv_error : NAN);
    for (std::size_t j = 0; j < cv.values.size(); ++j) rank.edges.push_back(j + 0.5);
    rank.series = {cv};
    try {
      draw(rank).write_png((fs::path(folder) / "ranking.png").string());
      figures.push_back("ranking.png");
    } catch (const std::exception& e) {
      std::cout << "no plot ranking.png: " << e.what() << "\n";
    }
  }

  std::ostringstream y;
  y << "# grainscale loop (" << version << " " << git_revision << "): residual -> missing effect -> added effect\n"
    << "settings: " << quoted(s.source_file) << "\nfit_settings: " << quoted(fit.source_file) << "\nmodel: " << quoted(fit.model_file)
    << "\ndata: {fields: " << quoted(fit.data.fields) << ", coverage: " << quoted(fit.data.coverage) << ", times: " << r.data.times.size()
    << ", field_observations: " << r.data.fields.size() << ", coverage_observations: " << r.data.coverage.size()
    << ", sigma_known: " << (r.data.sigma_known ? "true" : "false") << "}\n";
  if (s.motion) {
    y << "motion: {scenario: " << quoted(s.scenario_file) << ", container: " << s.motion->container << ", period: " << g(s.motion->period)
      << ", omega2_mean: " << g(s.motion->omega2_mean) << ", alpha2_mean: " << g(s.motion->alpha2_mean) << ", pause_fraction: " << g(s.motion->pause_fraction)
      << ", axis_x: " << g(s.motion->axis_x) << ", axis_z: " << g(s.motion->axis_z) << ", peak_angle_deg: " << g(s.motion->peak_angle_deg)
      << "}\n";
  }
  y << "selection: {min_cv_gain: " << g(s.min_cv_gain) << ", bic_drop: " << g(s.bic_drop) << ", cv_blocks: " << s.cv.blocks << "}\n"
    << "base:\n";
  yaml_evaluation(y, r.base, "  ");
  y << "diagnosis_before:\n";
  yaml_diagnosis(y, r.diagnosis_before);
  y << "candidates:   # ranked by cross-validated error\n";
  for (const auto& e : r.candidates) {
    y << "  - name: " << e.name << "\n";
    yaml_evaluation(y, e, "    ");
    if (e.ok) y << "    delta_aic: " << g(e.aic - r.base.aic) << "\n    delta_bic: " << g(e.bic - r.base.bic) << "\n";
  }
  y << "chosen: " << (chosen ? chosen->name : std::string("none")) << "\nreason: " << quoted(r.reason) << "\ndiagnosis_after:\n";
  yaml_diagnosis(y, r.diagnosis_after);

  std::ostringstream m;
  m << "# Closing the loop: residual, missing effect, added effect\n\n"
    << "Settings `" << s.source_file << "`; base fit settings `" << fit.source_file << "`, model `" << fit.model_file
    << "`. grainscale " << version << " (" << git_revision << ").\n\n"
    << "Data: " << r.data.fields.size() << " field and " << r.data.coverage.size() << " coverage observations at "
    << r.data.times.size() << " times" << (r.data.sigma_known ? " with given sigma" : " without sigma (unit weights; noise estimated)")
    << ".\n\n";
  if (s.motion) {
    m << "Motion (from `" << s.scenario_file << "`, wall `" << s.motion->container << "`): period " << s4(s.motion->period)
      << " s, peak tilt " << s4(s.motion->peak_angle_deg) << " deg, <omega^2> = " << s4(s.motion->omega2_mean)
      << " 1/s^2, <alpha^2> = " << s4(s.motion->alpha2_mean) << " 1/s^4, paused " << s4(100 * s.motion->pause_fraction) << " % of the cycle, rotation axis at x = "
      << s4(s.motion->axis_x) << " m, z = " << s4(s.motion->axis_z) << " m in the container frame.\n\n";
  }
  m << "## Decision\n\n**" << (chosen ? "Added: " + chosen->name : std::string("Nothing added")) << ".** " << r.reason << ".\n\n";
  if (chosen) {
    m << "Fitted strength:\n\n| parameter | value | standard error |\n|---|---|---|\n";
    for (std::size_t j = 0; j < chosen->parameters.size(); ++j) {
      m << "| `" << chosen->parameters[j] << "` | " << s4(chosen->values[j]) << " | " << s4(chosen->standard_errors[j]) << " |\n";
    }
    m << "\n";
  }
  const Evaluation& after = chosen ? *chosen : r.base;
  m << "## Error before and after\n\n| | before (base) | after |\n|---|---|---|\n"
    << "| RMS (model - data)/sigma | " << s4(r.base.rms) << " | " << s4(after.rms) << " |\n"
    << "| cross-validated error (held-out RMS r, " << r.base.cv_by << " blocks) | " << s4(r.base.cv_error) << " | " << s4(after.cv_error) << " |\n"
    << "| CV error beyond the noise, sqrt(max(cv^2 - 1, 0)) (given sigma) | " << s4(r.base.cv_model_error) << " | "
    << s4(after.cv_model_error) << " |\n"
    << "| RMSE fields (c) | " << s4(r.base.rmse_fields) << " | " << s4(after.rmse_fields) << " |\n"
    << "| max error fields | " << s4(r.base.max_fields) << " | " << s4(after.max_fields) << " |\n"
    << "| CV RMSE fields | " << s4(r.base.cv_rmse_fields) << " | " << s4(after.cv_rmse_fields) << " |\n"
    << "| RMSE coverage | " << s4(r.base.rmse_coverage) << " | " << s4(after.rmse_coverage) << " |\n"
    << "| max error coverage | " << s4(r.base.max_coverage) << " | " << s4(after.max_coverage) << " |\n"
    << "| CV RMSE coverage | " << s4(r.base.cv_rmse_coverage) << " | " << s4(after.cv_rmse_coverage) << " |\n"
    << "| residual | " << verdict(r.diagnosis_before) << " | " << verdict(r.diagnosis_after) << " |\n\n"
    << "## 1. Base fit\n\n| parameter | value | standard error |\n|---|---|---|\n";
  for (std::size_t j = 0; j < r.base.parameters.size(); ++j) {
    m << "| `" << r.base.parameters[j] << "` | " << s4(r.base.values[j]) << " | " << s4(r.base.standard_errors[j]) << " |\n";
  }
  m << "\nchi2 = " << s4(r.base.chi2) << " for " << r.base.n << " observations (" << r.base.fit.iterations << " iterations, "
    << (r.base.fit.converged ? "converged" : "NOT converged") << ").\n\n## 2. Diagnosis of the base residual\n\n";
  md_diagnosis(m, r.diagnosis_before);
  m << "## 3. Candidate effects, ranked by blocked cross-validation\n\n"
    << "Each candidate is fitted together with the base parameters, from the base optimum. CV: " << s.cv.blocks << " "
    << r.base.cv_by << " blocks, each held out in turn. Justified: held-out chi2 at least " << s4(100 * s.min_cv_gain)
    << " % below the base's, BIC at least " << s4(s.bic_drop) << " below, strength constrained (standard error below it, not at the edge of its admissible range).\n\n"
    << "| rank | candidate | fitted strength | CV error | dAIC | dBIC | iterations | s | notes |\n|---|---|---|---|---|---|---|---|---|\n"
    << "| 0 | base | - | " << s4(r.base.cv_error) << " | 0 | 0 | " << r.base.fit.iterations << " | " << s4(r.base.seconds) << " | |\n";
  for (std::size_t j = 0; j < r.candidates.size(); ++j) {
    const Evaluation& e = r.candidates[j];
    m << "| " << j + 1 << " | " << e.name << " | ";
    if (!e.ok) {
      m << "- | - | - | - | - | - | not ranked: " << e.error << " |\n";
      continue;
    }
    for (std::size_t p = r.base.parameters.size(); p < e.parameters.size(); ++p) {
      m << "`" << e.parameters[p] << "` = " << s4(e.values[p]) << " +- " << s4(e.standard_errors[p]) << " ";
    }
    m << "| " << s4(e.cv_error) << " | " << s4(e.aic - r.base.aic) << " | " << s4(e.bic - r.base.bic) << " | " << e.fit.iterations
      << " | " << s4(e.seconds) << " | ";
    for (const auto& w : e.warnings) m << w << "; ";
    m << "|\n";
  }
  if (chosen) {
    m << "\n## 4. After adding " << chosen->name << "\n\n";
    md_diagnosis(m, r.diagnosis_after);
  }
  m << "## Figures\n\n";
  for (const auto& f : figures) m << "![" << f << "](" << f << ")\n\n";

  std::vector<std::string> files;
  const std::string yaml = (fs::path(folder) / "loop.yaml").string(), md = (fs::path(folder) / "report.md").string();
  dem::write_file_atomically(yaml, y.str());
  dem::write_file_atomically(md, m.str());
  const std::string csv = (fs::path(folder) / "residuals.csv").string();
  dem::write_file_atomically(csv, residuals_csv(grid, r, chosen));
  files = {yaml, md, csv};
  for (const auto& f : figures) files.push_back((fs::path(folder) / f).string());
  return files;
}

}  // namespace grainscale::studies
