#include "studies/hold_study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <tuple>

#include "continuum/observation.hpp"
#include "dem/input_error.hpp"
#include "studies/hold_measures.hpp"
#include "studies/hold_output.hpp"
#include "studies/hold_run.hpp"
#include "studies/hold_study_report.hpp"
#include "studies/study_folder.hpp"

namespace grainscale::studies {

namespace {

std::string num(double v, int digits = 4) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

/// Mean of v over the columns whose centres lie in [a, b].
double mean_over(const continuum::Grid& g, const std::vector<double>& v, double a, double b) {
  double sum = 0;
  int n = 0;
  for (int i = 0; i < g.nx(); ++i) {
    if (g.x_centre(i) >= a && g.x_centre(i) <= b) sum += v[i], ++n;
  }
  return n ? sum / n : NAN;
}

std::string describe(const HoldSettings& s) {
  std::ostringstream w;
  std::string motion = s.motion->describe();
  while (!motion.empty() && (motion.back() == ';' || motion.back() == ' ')) motion.pop_back();
  w << num(s.length) << " m x " << num(s.depth) << " m " << s.direction << " section, filled to " << num(s.fill_height)
    << " m" << (s.decked ? " under a deck" : "") << "; " << motion;
  return w.str();
}

HoldScenarioOutcome run_scenario(const HoldStudyScenario& sc, StudyFolder& folder) {
  HoldSettings s = sc.settings;
  s.output_folder = folder.path(s.name);
  HoldScenarioOutcome o;
  o.name = s.name, o.file = sc.file, o.folder = s.name, o.what = describe(s);
  o.t_end = s.t_end, o.file_end = sc.file_end, o.chunk = s.chunk;
  o.shortened = sc.shortened, o.compare_with_report = sc.compare_with_report;
  o.top_layer = s.top_layer, o.end_zone = s.end_zone, o.spear_depth = s.spear_depth, o.dirty_factor = s.dirty_factor;
  o.length = s.length, o.c_initial = s.chaff_initial;
  o.total_chunks = static_cast<long>(std::ceil(s.t_end / s.chunk - 1e-9));
  folder.log("scenario " + s.name + " (" + sc.file + "): " + o.what + "; " + num(s.t_end) + " s" +
             (sc.shortened ? " (shortened from " + num(sc.file_end) + " s)" : ""));

  std::unique_ptr<HoldModel> model;
  const HoldResult r = run_hold(s, model, &std::cerr);
  const HoldFiles f = write_hold_output(s, *model, r);
  o.wall_seconds = r.wall_seconds;
  o.resolved_chunks = r.resolved_chunks, o.closure_steps = r.closure_steps, o.chaff_steps = r.chaff_steps;
  o.averaged = r.averaged.back() != 0;
  o.chaff_relative_change = r.chaff_initial > 0 ? (r.chaff_final - r.chaff_initial) / r.chaff_initial : 0.0;
  o.c_min = r.c_min, o.c_max = r.c_max;

  const continuum::Grid& g = model->model().grid();
  const double L = g.length(), z = s.end_zone;
  const std::vector<double> uniform(r.fields.front().size(), s.chaff_initial);
  std::tie(o.uniform_left, o.uniform_right) = end_top_fractions(g, uniform, s.top_layer, s.end_zone);
  o.times = r.times;
  for (const auto& c : r.fields) {
    const auto [l, rr] = end_top_fractions(g, c, s.top_layer, s.end_zone);
    o.left_share.push_back(l), o.right_share.push_back(rr);
    const auto surf = surface_concentration(g, c);
    o.surface_left.push_back(mean_over(g, surf, 0, z));
    o.surface_right.push_back(mean_over(g, surf, L - z, L));
    o.surface_centre.push_back(mean_over(g, surf, L / 2 - z / 2, L / 2 + z / 2));
  }
  o.enrichment_left = o.uniform_left > 0 ? o.left_share.back() / o.uniform_left : NAN;
  o.enrichment_right = o.uniform_right > 0 ? o.right_share.back() / o.uniform_right : NAN;
  const auto spear = spear_profile(g, r.fields.back(), s.spear_depth, s.chaff_initial);
  o.spear_max = *std::max_element(spear.begin(), spear.end());
  for (std::size_t k = 0; k < f.dirty_from.size(); ++k) o.dirty.push_back({f.dirty_from[k], f.dirty_to[k]});
  {  // what a photograph from above sees: chaff in the top grain diameter (coverage's argument, (O1))
    const continuum::SurfaceCoverage eye(1.0, s.friction.grain_diameter);
    const auto top = eye.top_layer_content(g, r.fields.back());
    const double centre = mean_over(g, top, L / 2 - z / 2, L / 2 + z / 2);
    o.visible_ratio_left = centre > 0 ? mean_over(g, top, 0, z) / centre : NAN;
    o.visible_ratio_right = centre > 0 ? mean_over(g, top, L - z, L) / centre : NAN;
  }
  for (const std::string& p : f.written) {
    if (p.size() > 4 && p.substr(p.size() - 4) == ".png") o.figures.push_back(s.name + "/" + p.substr(p.rfind('/') + 1));
  }
  folder.log("scenario " + s.name + " done in " + num(o.wall_seconds, 3) + " s of wall clock (" +
             std::to_string(o.resolved_chunks) + "/" + std::to_string(o.total_chunks) + " cycles resolved" +
             (o.averaged ? ", then the cycle-averaged model" : "") + "); end enrichment left " + num(o.enrichment_left, 3) +
             ", right " + num(o.enrichment_right, 3) + "; output " + s.output_folder);
  return o;
}

}  // namespace

HoldStudyResults run_hold_study(const HoldStudySettings& s, const StudyOptions& options, std::string& report_path) {
  const double t0 = wall_seconds_now();
  std::vector<std::string> inputs{s.source_file};
  for (const auto& sc : s.scenarios) inputs.push_back(sc.file);
  if (s.validate) inputs.push_back(s.validate->dem_scenario);
  StudyFolder folder(options.output_override.empty() ? s.output_directory : options.output_override, inputs, false);
  folder.log("hold study " + s.name + " (" + s.source_file + "): " + std::to_string(s.scenarios.size()) + " scenarios");
  if (options.resume) folder.log("--resume: a hold study has no checkpoint; every scenario runs again");
  HoldStudyResults res;
  for (const HoldStudyScenario& sc : s.scenarios) {
    res.scenarios.push_back(run_scenario(sc, folder));
    const HoldScenarioOutcome& o = res.scenarios.back();
    if (std::fabs(o.chaff_relative_change) > 1e-6) {
      res.warnings.push_back(o.name + ": chaff changed by " + num(100 * o.chaff_relative_change, 3) +
                             " % over the run (the model conserves it to round-off; a step-size problem?)");
    }
    if (o.shortened) {
      res.warnings.push_back(o.name + ": shortened by the study file to " + num(o.t_end) + " s (its own file runs " +
                             num(o.file_end) + " s); its numbers are not the full scenario's");
    }
    const double per_day = o.wall_seconds / o.t_end * 86400;
    if (o.t_end >= 3600 && per_day > 600) {
      res.warnings.push_back(o.name + ": " + num(per_day, 3) + " s of wall clock per simulated day, above issue 8's 600 s");
    }
  }
  if (s.validate) {
    const HoldStudyValidation& v = *s.validate;
    const double tv = wall_seconds_now();
    const auto it = std::find_if(s.scenarios.begin(), s.scenarios.end(),
                                 [&](const HoldStudyScenario& sc) { return sc.settings.name == v.material_from; });
    folder.log("closure vs DEM: " + v.cg_fields + " (scenario " + v.dem_scenario + "), friction of " + v.material_from);
    std::filesystem::create_directories(folder.path("closure_vs_dem"));
    res.validation = compare_closure_with_dem(v.cg_fields, v.dem_scenario, v.container, it->settings,
                                              folder.path("closure_vs_dem"), v.fit, v.measure_depth);
    folder.log("closure vs DEM done in " + num(wall_seconds_now() - tv, 3) + " s: surface angle RMS error " +
               num(res.validation->angle_rms_error_deg, 3) + " deg, surface speed RMS error " +
               num(res.validation->speed_rms_error, 3) + " m/s" +
               (res.validation->fit ? "; fitted closure on the test frames: " +
                                          num(res.validation->fit->fitted_test.angle_rms_deg, 3) + " deg, " +
                                          num(res.validation->fit->fitted_test.speed_rms, 3) + " m/s"
                                    : std::string()));
  }
  res.wall_seconds = wall_seconds_now() - t0;
  report_path = write_hold_study_report(s, res, folder.directory());
  folder.log("report " + report_path + " (" + num(res.wall_seconds, 3) + " s in all)");
  return res;
}

std::string hold_study_runner(const std::string& study_file, const StudyOptions& options) {
  const HoldStudySettings s = load_hold_study_settings(study_file);
  std::string report;
  (void)run_hold_study(s, options, report);
  return report;
}

}  // namespace grainscale::studies
