#include "studies/study_report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "dem/atomic_file.hpp"
#include "studies/cg_plots.hpp"
#include "studies/plot.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string g(double v, int digits = 4) {
  if (!std::isfinite(v)) return "n/a";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string pct(double v) { return std::isfinite(v) ? g(100 * v, 3) + " %" : "n/a"; }

std::string ratio(double ends, double centre) { return centre > 0 && std::isfinite(ends) ? g(ends / centre, 3) : "n/a"; }

std::string get(const std::map<std::string, std::string>& m, const std::string& k) {
  const auto it = m.find(k);
  return it == m.end() ? "n/a" : it->second;
}

/// A figure line if the file exists (relative to the report), else a note.
std::string figure(const std::string& out, const std::string& rel, const std::string& caption) {
  if (!fs::exists(fs::path(out) / rel)) return "*(" + caption + ": not drawn)*\n\n";
  return "![" + caption + "](" + rel + ")\n\n*" + caption + "*\n\n";
}

}  // namespace

std::string write_study_report(const StudySettings& s, const StudyResults& r, const std::string& out) {
  std::ostringstream m;
  m << "# " << s.title << "\n\n";
  if (!s.description.empty()) m << s.description << "\n\n";
  m << "Study `" << s.name << "`, run with `grainscale study " << s.source_file << "`. Inputs as run: `inputs/`; "
    << "the stage files the study generated (each runnable alone with `grainscale dem|cg|fit|predict`): `stages/`; "
    << "log: `log.txt`.\n\n";

  m << "## What was run\n\n| stage | result | wall clock |\n|---|---|---|\n";
  double total = 0;
  for (const auto& st : r.stages) {
    m << "| " << st.name << " | " << st.what << " | " << g(st.wall_seconds, 3) << " s |\n";
    total += st.wall_seconds;
  }
  m << "| total | | " << g(total, 3) << " s (" << g(total / 60, 2) << " min) |\n\n";

  if (!r.warnings.empty()) {
    m << "## Warnings\n\n";
    for (const auto& w : r.warnings) m << "- " << w << "\n";
    m << "\n";
  }

  m << "## 1. DEM (`dem/`)\n\n"
    << "Scenario `" << s.scenario << "` (copied to `inputs/`). Snapshots in `dem/snapshots/`, ParaView: open "
    << "`dem/snapshots.xmf`.\n\n| quantity | value |\n|---|---|\n";
  for (const char* k : {"spheres", "bodies", "simulated_time_s", "time_step_s", "steps", "wall_clock_s",
                        "sphere_steps_per_s", "max_overlap_ratio", "max_step_stability_margin", "kinetic_energy_J"}) {
    m << "| " << k << " | " << get(r.dem_summary, k) << " |\n";
  }
  m << "\n## 2. Coarse-graining (`cg/`)\n\n"
    << r.cg_snapshots << " snapshots coarse-grained in the box's own frame (fields: `cg/fields.h5`, ParaView "
    << "`cg/fields.xmf`; CSV beside them); worst mass error " << g(r.cg_mass_error, 2) << ". The continuum "
    << "model's flow is the average of the " << r.flow_snapshots << " snapshots between " << g(s.flow_from)
    << " s and the end of the motion (`cg_flow/`).\n\n"
    << "| measure | first snapshot (t = " << g(r.dem_t_first) << " s) | last snapshot (t = " << g(r.dem_t_last)
    << " s) |\n|---|---|---|\n"
    << "| top-view chaff coverage, centre | " << pct(r.dem_coverage_centre_first) << " | " << pct(r.dem_coverage_centre)
    << " |\n"
    << "| top-view chaff coverage, ends (mean) | " << pct(r.dem_coverage_ends_first) << " | "
    << pct(0.5 * (r.dem_coverage_left + r.dem_coverage_right)) << " |\n"
    << "| congregation index left / right (1 = uniform) | | " << g(r.dem_index_left, 3) << " / "
    << g(r.dem_index_right, 3) << " |\n\n";
  m << figure(out, "cg/slices.png", "Chaff per 50 mm slice, first and last snapshot (the report's Figure 11)");
  m << figure(out, "cg/coverage.png", "Top-view chaff coverage along the box");
  m << figure(out, "cg/congregation.png", "Congregation index over time");
  m << figure(out, "cg/concentration.png", "Chaff concentration c(x, z), last snapshot");

  m << "## 3. Fit (`fit/`)\n\n"
    << "The continuum model (`stages/model.yaml`, terms and priors: docs/continuum.md) carried by the "
    << "coarse-grained flow, starting at t0 = " << g(r.t0) << " s from a uniform c = " << g(r.initial_c, 3)
    << " (the DEM's mean), fitted to " << r.fit_frames << " coarse-grained frames "
    << (s.fit_fields ? "of c(x, z)" : "") << (s.fit_fields && s.fit_coverage ? " and " : "")
    << (s.fit_coverage ? "of top-view coverage" : "") << ". " << (r.fit_converged ? "Converged" : "Did not converge")
    << " after " << r.fit_iterations << " iterations, chi2/dof = " << g(r.chi2_per_dof, 3) << ".\n\n"
    << "| parameter | start | fitted | standard error |\n|---|---|---|---|\n";
  for (std::size_t j = 0; j < r.fit_names.size(); ++j) {
    m << "| " << r.fit_names[j] << " | " << (j < r.fit_starts.size() ? g(r.fit_starts[j]) : "") << " | "
      << g(r.fit_values[j]) << " | " << g(r.fit_errors[j], 2) << " |\n";
  }
  m << "\nDetails, correlations and residuals: `fit/report.md`.\n\n";
  m << figure(out, "fit/fields_last.png", "Last fitted frame: DEM data, model, residual");
  m << figure(out, "fit/coverage.png", "Coverage: DEM data (points) and fitted model (lines)");

  m << "## 4. Prediction (`predict/`)\n\n"
    << "The fitted model run for " << g(r.predict_end) << " s of motion (`stages/predict.yaml`). Chaff per unit "
    << "width " << g(r.chaff_initial, 6) << " -> " << g(r.chaff_final, 6) << " m^2 (conserved to "
    << g(r.chaff_initial > 0 ? std::fabs(r.chaff_final - r.chaff_initial) / r.chaff_initial : 0, 2)
    << " relative); c stayed in [" << g(r.c_min, 3) << ", " << g(r.c_max, 3) << "].\n\n";
  m << figure(out, "predict/coverage.png", "Predicted top-view coverage along the box");
  m << figure(out, "predict/coverage_time.png", "Predicted coverage in the centre and end zones over time");

  const double me = kReportCoverageEnds, mc = kReportCoverageCentre;
  m << "## 5. Comparison with the measurements\n\n"
    << "The source report photographed the wheat surface of its 800 x 200 x 200 mm box after 30 minutes on the "
    << "platform: about " << pct(mc) << " chaff pixels in the centre and about " << pct(me)
    << " at the ends (only the right-hand peak is trustworthy; ../shared/data/source_measurements.yaml). Zones "
    << "here: the outer " << g(s.end_length * 1000) << " mm at each end, and as long a zone in the centre.\n\n"
    << "| | centre | left end | right end | ends / centre |\n|---|---|---|---|---|\n"
    << "| measured (report, 1800 s) | " << pct(mc) << " | (artefact) | " << pct(me) << " | " << ratio(me, mc) << " |\n"
    << "| DEM, this study (t = " << g(r.dem_t_last) << " s) | " << pct(r.dem_coverage_centre) << " | "
    << pct(r.dem_coverage_left) << " | " << pct(r.dem_coverage_right) << " | "
    << ratio(r.dem_coverage_right, r.dem_coverage_centre) << " |\n"
    << "| continuum, fitted (t = " << g(r.predict_end) << " s) | " << pct(r.coverage_centre) << " | "
    << pct(r.coverage_left) << " | " << pct(r.coverage_right) << " | "
    << ratio(r.coverage_right, r.coverage_centre) << " |\n\n";
  const double pr = r.coverage_centre > 0 ? r.coverage_right / r.coverage_centre : NAN;
  m << "Verdict: ";
  if (!std::isfinite(pr)) {
    m << "the prediction has no coverage in the centre zone to compare.";
  } else if (pr > 0.5 * me / mc && pr < 2 * me / mc) {
    m << "the predicted right-end/centre coverage ratio (" << g(pr, 3) << ") is within a factor 2 of the measured "
      << g(me / mc, 2) << ".";
  } else {
    m << "the predicted right-end/centre coverage ratio (" << g(pr, 3) << ") is not within a factor 2 of the measured "
      << g(me / mc, 2) << ": the model, as fitted to this run, does not reproduce the congregation.";
  }
  m << " Read it with the limits below.\n\n"
    << "## Limits of this comparison\n\n"
    << "- The DEM box, fill, particle scale and motion are those of `" << s.scenario << "` (see its header), "
    << "not necessarily the report's; the measurement is from the report's 800 mm box.\n"
    << "- The fit sees only " << g(r.dem_t_last - r.t0, 3) << " s of DEM; the prediction extrapolates to "
    << g(r.predict_end) << " s with the flow averaged over that window (no phase resolution).\n"
    << "- Warnings above (narrow container, unconstrained parameters) say where the numbers are weakest.\n";
  const std::string path = (fs::path(out) / "report.md").string();
  dem::write_file_atomically(path, m.str());
  return path;
}

void write_prediction_figures(const NumericCsv& coverage, const std::string& folder, double end_length) {
  std::vector<double> x;
  std::vector<std::string> names;
  for (const auto& n : coverage.columns()) {
    if (n == "time_s") continue;
    x.push_back(std::stod(n));
    names.push_back(n);
  }
  if (x.empty() || coverage.rows() == 0) return;
  const std::vector<double> t = coverage.column("time_s");
  std::vector<std::vector<double>> rows(coverage.rows());
  for (const auto& n : names) {
    const std::vector<double> col = coverage.column(n);
    for (std::size_t k = 0; k < rows.size(); ++k) rows[k].push_back(col[k]);
  }
  LinePlot along;
  along.axes = {"Predicted top-view chaff coverage", "x along the box (m)", "coverage", std::nullopt, std::nullopt, 0.0, 1.0};
  const std::size_t shown = std::min<std::size_t>(6, rows.size());
  for (std::size_t j = 0; j < shown; ++j) {
    const std::size_t k = shown == 1 ? rows.size() - 1 : j * (rows.size() - 1) / (shown - 1);
    along.series.push_back({"t = " + g(t[k], 3) + " s", x, rows[k]});
  }
  draw(along).write_png((fs::path(folder) / "coverage.png").string());

  const double L = x.back() + x.front();
  auto zone = [&](const std::vector<double>& row, double a, double b) {
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (x[i] >= a && x[i] <= b) sum += row[i], ++n;
    return n ? sum / n : NAN;
  };
  Series centre{"centre", {}, {}}, left{"left end", {}, {}}, right{"right end", {}, {}};
  for (std::size_t k = 0; k < rows.size(); ++k) {
    centre.x.push_back(t[k]);
    left.x.push_back(t[k]);
    right.x.push_back(t[k]);
    centre.y.push_back(zone(rows[k], 0.5 * (L - end_length), 0.5 * (L + end_length)));
    left.y.push_back(zone(rows[k], 0, end_length));
    right.y.push_back(zone(rows[k], L - end_length, L));
  }
  const double t_end = t.back();
  Series mc{"measured centre (report)", {0, t_end}, {kReportCoverageCentre, kReportCoverageCentre}, LineStyle::dashed};
  Series me{"measured ends (report)", {0, t_end}, {kReportCoverageEnds, kReportCoverageEnds}, LineStyle::dashed};
  LinePlot over;
  over.axes = {"Predicted coverage in the centre and end zones", "time (s)", "coverage", std::nullopt, std::nullopt, 0.0, 1.0};
  over.series = {centre, left, right, mc, me};
  draw(over).write_png((fs::path(folder) / "coverage_time.png").string());
}

}  // namespace grainscale::studies
