#include "studies/study_run.hpp"

#include <omp.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>

#include "coarsegrain/cg_run.hpp"
#include "continuum/run_continuum.hpp"
#include "continuum/settings.hpp"
#include "dem/atomic_file.hpp"
#include "dem/dem_run.hpp"
#include "dem/input_error.hpp"
#include "dem/snapshot.hpp"
#include "studies/cg_plots.hpp"
#include "studies/fit_command.hpp"
#include "studies/numeric_csv.hpp"
#include "studies/study_report.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::string g(double v, int digits = 10) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

/// A stage file: the YAML with a header saying where it came from and how to run it alone.
void write_stage_file(const std::string& path, const YAML::Node& node, const std::string& header) {
  YAML::Emitter e;
  e << node;
  if (!e.good()) throw std::runtime_error("cannot write " + path + ": " + e.GetLastError());
  dem::write_file_atomically(path, header + e.c_str() + "\n");
}

YAML::Node load_yaml(const std::string& file) {
  try {
    return YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    throw InputError(file + ": " + e.what());
  }
}

/// Sorted distinct values.
std::vector<double> distinct(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

/// Snapshots are written at the first step at or after each output time, so "t >= from" must
/// allow a step's worth of slack: 1 % of the typical spacing of the (sorted) times.
double time_slack(const std::vector<double>& sorted) {
  if (sorted.size() < 2) return 0;
  std::vector<double> gaps;
  for (std::size_t k = 1; k < sorted.size(); ++k) gaps.push_back(sorted[k] - sorted[k - 1]);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  return 0.01 * gaps[gaps.size() / 2];
}

bool in(const std::vector<double>& sorted, double v) { return std::binary_search(sorted.begin(), sorted.end(), v); }

/// Mean coverage over [a, b] of one row of the continuum's coverage.csv (columns: column centres).
double zone_mean(const std::vector<double>& x, const std::vector<double>& values, double a, double b) {
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] >= a && x[i] <= b && std::isfinite(values[i])) {
      sum += values[i];
      ++n;
    }
  }
  return n ? sum / n : NAN;
}

}  // namespace

StudyRun::StudyRun(StudySettings settings, StudyOptions options) : s_(std::move(settings)), o_(std::move(options)) {
  out_ = o_.output_override.empty() ? s_.output_directory : o_.output_override;
}

std::string StudyRun::path(const std::string& relative) const { return fs::absolute(fs::path(out_) / relative).lexically_normal().string(); }

void StudyRun::log(const std::string& line) {
  if (folder_) folder_->log(line);
  else std::cerr << "[study] " << line << "\n";
}

void StudyRun::stage_done(const std::string& name, const std::string& what, double started) {
  results_.stages.push_back({name, what, now() - started});
  log(name + " done in " + g(now() - started, 3) + " s: " + what);
}

void StudyRun::setup() {
  // The inputs as they were: the study file and the stage files it names.
  folder_.emplace(out_, std::vector<std::string>{s_.source_file, s_.scenario, s_.cg_settings, s_.model}, o_.resume);
  std::error_code ec;
  fs::create_directories(path("stages"), ec);
  if (ec || !fs::is_directory(path("stages"))) throw std::runtime_error("cannot create " + path("stages") + ": " + ec.message());
  if (o_.threads > 0) omp_set_num_threads(o_.threads);
  log("study " + s_.name + " (" + s_.source_file + ") -> " + out_ + (o_.resume ? " (resuming)" : ""));
}

void StudyRun::run() {
  dem();
  coarse_grain();
  fit();
  predict();
}

void StudyRun::output() {
  const std::string report = write_study_report(s_, results_, out_);
  log("report: " + report);
}

// ---------------------------------------------------------------------------------------------
void StudyRun::dem() {
  const double started = now();
  log("stage 1/4: DEM, " + s_.scenario);
  const bool resume = o_.resume && fs::exists(path("dem/checkpoint.h5"));
  dem::DemRun run(s_.scenario, path("dem"), resume);
  run.setup();
  run.run();
  run.output();
  const YAML::Node summary = load_yaml(path("dem/summary.yaml"));
  for (const auto& kv : summary) {
    if (kv.second.IsScalar()) results_.dem_summary[kv.first.as<std::string>()] = kv.second.as<std::string>();
  }
  std::ifstream dem_log(path("dem/log.txt"));
  std::set<std::string> seen;  // a resumed run's log repeats the warnings of its setup
  for (std::string line; std::getline(dem_log, line);) {
    if (line.find("warning") != std::string::npos && seen.insert(line).second) results_.warnings.push_back("dem: " + line);
  }
  stage_done("dem", results_.dem_summary["spheres"] + " spheres, " + results_.dem_summary["simulated_time_s"] +
                        " s simulated", started);
  // A resumed run's wall clock includes the time before the interruption (summary.yaml).
  try {
    results_.stages.back().wall_seconds = std::max(results_.stages.back().wall_seconds, std::stod(results_.dem_summary["wall_clock_s"]));
  } catch (const std::exception&) {
  }
}

void StudyRun::coarse_grain() {
  const double started = now();
  log("stage 2/4: coarse-graining, " + s_.cg_settings);
  const std::string header = "# Generated by `grainscale study " + s_.source_file + "` from " + s_.cg_settings +
                             "\n# (snapshots and output set by the study). Run alone: grainscale cg THIS_FILE\n";
  YAML::Node node = load_yaml(s_.cg_settings);
  node.remove("snapshots");
  node["snapshot_dir"] = path("dem/snapshots");
  node["output"] = path("cg");
  write_stage_file(path("stages/cg.yaml"), node, header);
  const cg::CgSummary cs = cg::run_coarse_graining(cg::load_cg_settings(path("stages/cg.yaml")));
  std::ostringstream plot_log;
  const CgPlotReport plots = write_cg_plots(cs.output_dir, plot_log);
  results_.cg_figures = plots.written;
  for (const auto& skipped : plots.skipped) results_.warnings.push_back("cg: no figure " + skipped);
  results_.cg_snapshots = cs.snapshots;
  results_.cg_mass_error = cs.max_mass_error;
  if (!cs.congregation.empty()) {
    // "Before": the first snapshot once the motion starts (earlier ones may be mid-pour).
    std::size_t k0 = 0;
    while (k0 + 1 < cs.times.size() && cs.times[k0] < s_.flow_from - time_slack(cs.times)) ++k0;
    const cg::CongregationIndex& first = cs.congregation[k0];
    const cg::CongregationIndex& last = cs.congregation.back();
    results_.dem_t_first = cs.times[k0];
    results_.dem_t_last = cs.times.back();
    results_.dem_coverage_centre = last.coverage_centre;
    results_.dem_coverage_left = last.coverage_left;
    results_.dem_coverage_right = last.coverage_right;
    results_.dem_index_left = last.left;
    results_.dem_index_right = last.right;
    results_.dem_coverage_centre_first = first.coverage_centre;
    results_.dem_coverage_ends_first = 0.5 * (first.coverage_left + first.coverage_right);
  }

  // The bulk flow the continuum model is carried by: the window average of the snapshots in
  // [flow_from, flow_to] (the motion, not the pour).
  YAML::Node flow = load_yaml(s_.cg_settings);
  flow.remove("snapshot_dir");
  flow.remove("snapshots");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(path("dem/snapshots"))) {
    if (e.path().extension() == ".h5") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  std::vector<double> times;
  for (const auto& f : files) times.push_back(dem::read_snapshot(f).time);
  const double slack = time_slack(times);
  for (std::size_t k = 0; k < files.size(); ++k) {
    const std::string& f = files[k];
    const double t = times[k];
    if (t >= s_.flow_from - slack && t <= s_.flow_to + slack) {
      YAML::Node entry;
      entry["path"] = f;
      flow["snapshots"].push_back(entry);
      ++results_.flow_snapshots;
    }
  }
  if (results_.flow_snapshots == 0) {
    throw InputError(s_.source_file + ": cg.flow_from/flow_to: no snapshot of the DEM run lies in [" + g(s_.flow_from) +
                     ", " + g(s_.flow_to) + "] s");
  }
  flow["averaging"] = YAML::Node(YAML::NodeType::Map);
  flow["averaging"]["mode"] = "window";
  flow["output"] = path("cg_flow");
  write_stage_file(path("stages/cg_flow.yaml"), flow, header);
  cg::run_coarse_graining(cg::load_cg_settings(path("stages/cg_flow.yaml")));
  stage_done("cg", std::to_string(cs.snapshots) + " snapshots; flow averaged over " +
                       std::to_string(results_.flow_snapshots), started);
}

void StudyRun::fit() {
  const double started = now();
  log("stage 3/4: fit, " + s_.model);
  // The data: the coarse-grained fields and coverage from the first frame at or after data.from
  // (the model's initial state) on, every data.every-th frame.
  const NumericCsv fields = NumericCsv::load(path("cg/fields.csv"));
  const NumericCsv coverage = NumericCsv::load(path("cg/coverage.csv"));
  const std::vector<double> ft = fields.column("t_s"), fx = fields.column("x_m"), fz = fields.column("z_m"),
                            fc = fields.column("c"), fphi = fields.column("phi");
  // A cell belongs to the bed if its solid fraction reaches fit.data.min_solid_fraction: above the
  // surface the kernel still sees a few grains, and c there is noise, not bed.
  auto in_bed = [&](std::size_t r) { return std::isfinite(fc[r]) && fphi[r] >= s_.min_solid_fraction; };
  std::vector<double> frames;
  const std::vector<double> all_frames = distinct(ft);
  const double slack = time_slack(all_frames);
  for (double t : all_frames)
    if (t >= s_.data_from - slack) frames.push_back(t);
  if (frames.size() < 2) {
    throw InputError(s_.source_file + ": fit.data.from = " + g(s_.data_from) + " s leaves " +
                     std::to_string(frames.size()) + " coarse-grained frame(s); the fit needs the initial one and at least one more");
  }
  results_.t0 = frames.front();
  std::vector<double> used;
  for (std::size_t k = s_.data_every; k < frames.size(); k += s_.data_every) used.push_back(frames[k]);
  if (used.empty()) used.push_back(frames.back());
  results_.fit_frames = static_cast<int>(used.size());

  // The chaff is poured mixed with the grain: the model starts uniform at the DEM's mean c at t0.
  double sum = 0;
  int n = 0;
  std::ostringstream fcsv, ccsv;
  fcsv << "t_s,x_m,z_m,c\n";
  for (std::size_t r = 0; r < fields.rows(); ++r) {
    if (!in_bed(r)) continue;
    if (ft[r] == results_.t0) {
      sum += fc[r];
      ++n;
    }
    if (in(used, ft[r])) fcsv << g(ft[r]) << ',' << g(fx[r]) << ',' << g(fz[r]) << ',' << g(fc[r]) << '\n';
  }
  if (n == 0) {
    throw InputError(s_.source_file + ": fit.data.min_solid_fraction = " + g(s_.min_solid_fraction) + ": no cell of " +
                     path("cg/fields.csv") + " at t = " + g(results_.t0) +
                     " s has that much solid (a bed thinner than a cell? lower it or refine the cg grid)");
  }
  results_.initial_c = sum / n;
  const std::vector<double> ct = coverage.column("t_s"), cx = coverage.column("x_m"), cv = coverage.column("coverage");
  ccsv << "t_s,x_m,coverage\n";
  for (std::size_t r = 0; r < coverage.rows(); ++r) {
    if (in(used, ct[r])) ccsv << g(ct[r]) << ',' << g(cx[r]) << ',' << g(cv[r]) << '\n';
  }
  fs::create_directories(path("fit_data"));
  dem::write_file_atomically(path("fit_data/fields.csv"), fcsv.str());
  dem::write_file_atomically(path("fit_data/coverage.csv"), ccsv.str());

  // The model file with the study's flow and initial state.
  YAML::Node model = load_yaml(s_.model);
  YAML::Node flow;
  flow["type"] = "file";
  flow["file"] = path("cg_flow/fields.h5");
  model["flow"] = flow;
  if (model["grid"]) {
    model["grid"].remove("depth");
    model["grid"].remove("surface");
  }
  YAML::Node initial;
  initial["type"] = "uniform";
  initial["value"] = results_.initial_c;
  model["initial"] = initial;
  model["output"] = YAML::Node(YAML::NodeType::Map);
  model["output"]["folder"] = path("predict");
  write_stage_file(path("stages/model.yaml"), model,
                   "# Generated by `grainscale study " + s_.source_file + "` from " + s_.model +
                       "\n# (flow from the coarse-grained DEM, initial state from its first frame after data.from).\n");

  YAML::Node fit;
  fit["model"] = path("stages/model.yaml");
  if (s_.fit_fields) {
    fit["data"]["fields"] = path("fit_data/fields.csv");
    fit["data"]["field_sigma"] = s_.field_sigma;
  }
  if (s_.fit_coverage) {
    fit["data"]["coverage"] = path("fit_data/coverage.csv");
    fit["data"]["coverage_sigma"] = s_.coverage_sigma;
  }
  fit["data"]["t0"] = results_.t0;
  for (const auto& p : s_.fit_parameters) fit["fit"]["parameters"].push_back(p);
  fit["fit"]["max_iterations"] = s_.max_iterations;
  fit["output"] = path("fit");
  write_stage_file(path("stages/fit.yaml"), fit,
                   "# Generated by `grainscale study " + s_.source_file + "`. Run alone: grainscale fit THIS_FILE\n");

  const FitCommandSettings fit_settings = load_fit_command_settings(path("stages/fit.yaml"));
  const FitCommandSummary fitted = run_fit_command(fit_settings);
  const continuum::FitResult& r = fitted.result;
  results_.fit_names = r.names;
  results_.fit_values = r.values;
  results_.fit_errors = r.standard_errors;
  results_.fit_starts = fitted.start_values;
  results_.chi2_per_dof = r.dof > 0 ? r.chi2 / r.dof : NAN;
  results_.fit_iterations = r.iterations;
  results_.fit_converged = r.converged;
  for (const auto& w : fitted.warnings) results_.warnings.push_back("fit: " + w);
  std::string what = std::to_string(used.size()) + " frames from t0 = " + g(results_.t0, 4) + " s:";
  for (std::size_t j = 0; j < r.names.size(); ++j) what += " " + r.names[j] + " = " + g(r.values[j], 4);
  stage_done("fit", what, started);
}

void StudyRun::predict() {
  const double started = now();
  log("stage 4/4: prediction to " + g(s_.predict_end) + " s");
  YAML::Node model = load_yaml(path("stages/model.yaml"));
  for (std::size_t j = 0; j < results_.fit_names.size(); ++j) {
    const std::string& q = results_.fit_names[j];
    const auto dot = q.find('.');
    const std::string group = q.substr(0, dot), key = q.substr(dot + 1);
    if (group == "observation") model["observation"][key] = results_.fit_values[j];
    else model["terms"][group][key] = results_.fit_values[j];
  }
  model["time"] = YAML::Node(YAML::NodeType::Map);
  model["time"]["end"] = s_.predict_end;
  model["time"]["outputs"] = s_.predict_outputs;
  model["output"]["folder"] = path("predict");
  write_stage_file(path("stages/predict.yaml"), model,
                   "# Generated by `grainscale study " + s_.source_file +
                       "`: the model with the fitted coefficients. Run alone: grainscale predict THIS_FILE\n");
  const continuum::ContinuumRunSummary r = continuum::run_continuum(continuum::load_continuum_settings(path("stages/predict.yaml")));
  results_.predict_end = s_.predict_end;
  results_.chaff_initial = r.chaff_initial;
  results_.chaff_final = r.chaff_final;
  results_.c_min = r.c_min;
  results_.c_max = r.c_max;

  // Coverage in the centre and end zones, first and last output (columns are the column centres).
  const NumericCsv cov = NumericCsv::load(r.coverage_file);
  std::vector<double> x;
  std::vector<std::vector<double>> rows(cov.rows());
  for (const auto& name : cov.columns()) {
    if (name == "time_s") continue;
    x.push_back(std::stod(name));
    const std::vector<double> col = cov.column(name);
    for (std::size_t k = 0; k < cov.rows(); ++k) rows[k].push_back(col[k]);
  }
  const double L = x.empty() ? 0 : x.back() + x.front();  // centres of equal columns
  const double e = s_.end_length, mid = 0.5 * L;
  results_.coverage_left = zone_mean(x, rows.back(), 0, e);
  results_.coverage_right = zone_mean(x, rows.back(), L - e, L);
  results_.coverage_centre = zone_mean(x, rows.back(), mid - 0.5 * e, mid + 0.5 * e);
  results_.coverage_centre_first = zone_mean(x, rows.front(), mid - 0.5 * e, mid + 0.5 * e);
  results_.coverage_ends_first = 0.5 * (zone_mean(x, rows.front(), 0, e) + zone_mean(x, rows.front(), L - e, L));
  write_prediction_figures(cov, path("predict"), e);
  stage_done("predict", "coverage at " + g(s_.predict_end, 4) + " s: centre " + g(results_.coverage_centre, 3) +
                            ", ends " + g(results_.coverage_left, 3) + " / " + g(results_.coverage_right, 3),
             started);
}

}  // namespace grainscale::studies
