#include "studies/calibrate_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <omp.h>

#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "dem/simulation.hpp"
#include "grainscale_version.hpp"
#include "studies/aor_materials_file.hpp"
#include "studies/aor_profile_plot.hpp"
#include "studies/aor_run.hpp"
#include "studies/aor_search.hpp"
#include "studies/aor_sensitivity_plot.hpp"
#include "studies/aor_study.hpp"
#include "studies/option_number.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

/// One DEM run of the study.
struct RunRow {
  std::string case_name;
  int point = 0;  // search point (1-based)
  std::uint64_t seed = 0;
  std::vector<double> values;
  bool ok = false;
  std::string error;  // why there is no angle
  AorRunResult r;
};

/// One search point: the values and the angle averaged over the seeds.
struct PointSummary {
  double t = 0;
  std::vector<double> values;
  double angle = std::numeric_limits<double>::quiet_NaN();  // mean over seeds
  double seed_spread = 0;   // standard deviation over seeds (0 with one seed)
  double sector_spread = 0; // mean over seeds of the sector spread
  double side = std::numeric_limits<double>::quiet_NaN();
};

struct CaseOutcome {
  const CalibrationCase* c = nullptr;
  SearchResult search;
  std::vector<PointSummary> points;
  std::vector<double> chosen;      // parameter values written to the calibrated file
  bool chosen_verified = false;    // a run at exactly these values met the tolerance
  double chosen_angle = std::numeric_limits<double>::quiet_NaN();  // of the best run
  std::string materials_file, png_file;
};

std::string csv(const std::vector<RunRow>& rows, const CalibrationStudy& s) {
  std::size_t n_par = 0;
  for (const auto& c : s.cases) n_par = std::max(n_par, c.parameters.size());
  std::ostringstream o;
  o << "case,point,seed";
  for (std::size_t k = 0; k < n_par; ++k) o << ",parameter_" << k + 1 << ",value_" << k + 1;
  o << ",angle_deg,sector_spread_deg,side_angle_deg,side_spread_deg,at_rest,particles,on_tray,lift_start_s,"
       "end_time_s,time_step_s,wall_clock_s,warnings,error\n";
  for (const RunRow& r : rows) {
    const CalibrationCase* c = nullptr;
    for (const auto& k : s.cases) {
      if (k.name == r.case_name) c = &k;
    }
    o << r.case_name << "," << r.point << "," << r.seed;
    for (std::size_t k = 0; k < n_par; ++k) {
      if (c && k < c->parameters.size()) o << "," << c->parameters[k].label() << "," << r.values[k];
      else o << ",,";
    }
    const AngleMeasurement& a = r.r.angle;
    if (r.ok) {
      o << "," << a.mean_deg << "," << a.spread_deg << "," << a.side_mean_deg << "," << a.side_spread_deg << ","
        << (r.r.at_rest ? 1 : 0) << "," << r.r.bodies << "," << r.r.bodies_on_tray << "," << r.r.lift_start << ","
        << r.r.end_time << "," << r.r.time_step << "," << r.r.wall_seconds << "," << r.r.warnings.size() << ",";
    } else {
      o << ",,,,,,,,,,,," << r.r.wall_seconds << ",," << '"' << r.error << '"';
    }
    o << "\n";
  }
  return o.str();
}

std::string report_md(const CalibrationStudy& s, const std::vector<CaseOutcome>& outcomes, const std::vector<RunRow>& rows,
                      double wall_total) {
  std::ostringstream m;
  m << "# Angle-of-repose calibration: " << s.name << "\n\n"
    << "grainscale " << version << " (" << git_revision << "), study `" << s.file << "`, materials `" << s.materials_file
    << "`.\n\n"
    << "Rig (docs/aor_calibration.md): pipe " << fixed(s.rig.pipe_diameter * 1e3, 1) << " mm x "
    << fixed(s.rig.pipe_length * 1e3, 1) << " mm lifted at " << fixed(s.rig.lift_speed * 1e3, 1) << " mm/s, tray "
    << fixed(s.rig.tray_diameter * 1e3, 1) << " mm with a " << fixed(s.rig.tray_rim_height * 1e3, 1) << " mm rim, walls "
    << s.rig.wall_material << ". Particles at " << s.scale_factor << "x size; rolling model " << s.rolling_model
    << ", rolling friction rule `" << dem::rolling_friction_rule_name(s.scaling.rolling) << "` (calibrated_at "
    << s.scaling.calibrated_at << ", docs/scaling.md). Time step " << s.timing.step_fraction
    << " of the Rayleigh time. Seeds per point: " << s.seeds.size() << "; tolerance " << s.tolerance_deg
    << " deg; at most " << s.max_runs << " points per case.\n\n"
    << "The angle is the mean over " << 8 << " azimuthal sectors of a fit of the pile's free surface between 20 % "
    << "and 80 % of its height (studies/aor_angle.hpp); 'side' is the silhouette from four side views, like the "
    << "report's image processing.\n\n";
  for (const CaseOutcome& o : outcomes) {
    const CalibrationCase& c = *o.c;
    m << "## " << c.name << "\n\n"
      << "Target " << fixed(c.target_deg, 2) << " deg (" << c.target_source << ")";
    for (const auto& r : c.references) m << "; " << r.label << " " << fixed(r.deg, 2) << " deg";
    m << ". Searched: ";
    for (std::size_t k = 0; k < c.parameters.size(); ++k) {
      m << (k ? ", " : "") << "`" << c.parameters[k].label() << "` in [" << c.parameters[k].lo << ", "
        << c.parameters[k].hi << "]";
    }
    m << (c.parameters.size() > 1 ? " (together, along the line between the ranges' ends)" : "") << ".\n\n";
    m << "| point |";
    for (const auto& p : c.parameters) m << " " << p.label() << " |";
    m << " angle (deg) | seed spread | sector spread | side (deg) |\n|---|";
    for (std::size_t k = 0; k < c.parameters.size(); ++k) m << "---|";
    m << "---|---|---|---|\n";
    for (std::size_t i = 0; i < o.points.size(); ++i) {
      const PointSummary& p = o.points[i];
      m << "| " << i + 1 << " |";
      for (double v : p.values) m << " " << fixed(v, 4) << " |";
      m << " " << fixed(p.angle, 2) << " | " << fixed(p.seed_spread, 2) << " | " << fixed(p.sector_spread, 2) << " | "
        << fixed(p.side, 2) << " |\n";
    }
    m << "\nSearch: " << o.search.status << ".\n\n";
    m << "**Result:** ";
    for (std::size_t k = 0; k < c.parameters.size(); ++k) {
      m << (k ? ", " : "") << "`" << c.parameters[k].label() << "` = " << fixed(o.chosen[k], 4);
    }
    if (o.chosen_verified) {
      m << ", verified by a run at " << fixed(o.chosen_angle, 2) << " deg (target " << fixed(c.target_deg, 2) << ").";
    } else if (o.search.bracketed) {
      m << ", interpolated between the bracketing runs (not verified by a run; the closest run gave "
        << fixed(o.chosen_angle, 2) << " deg).";
    } else {
      m << ", the closest run (" << fixed(o.chosen_angle, 2) << " deg): the target was not reached.";
    }
    m << " Calibrated materials: `" << fs::path(o.materials_file).filename().string() << "`; figure: `"
      << fs::path(o.png_file).filename().string() << "`.\n\n";
    for (const auto& r : c.references) {
      m << "- against " << r.label << " (" << fixed(r.deg, 2) << " deg): the closest run differs by "
        << fixed(o.chosen_angle - r.deg, 2) << " deg.\n";
    }
    std::vector<std::string> warnings;
    for (const RunRow& r : rows) {
      if (r.case_name != c.name) continue;
      for (const std::string& w : r.r.warnings) {
        if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(w);
      }
      if (!r.ok) warnings.push_back("point " + std::to_string(r.point) + ", seed " + std::to_string(r.seed) + ": " + r.error);
    }
    if (!warnings.empty()) {
      m << "\nWarnings:\n\n";
      for (const std::string& w : warnings) m << "- " << w << "\n";
    }
    m << "\n";
  }
  double wall = 0;
  std::size_t n = 0, particles = 0;
  for (const RunRow& r : rows) wall += r.r.wall_seconds, ++n, particles = std::max(particles, r.r.bodies);
  m << "## Cost\n\n"
    << n << " DEM runs, " << fixed(wall / 60, 1) << " min of wall clock in the runs (" << fixed(wall_total / 60, 1)
    << " min in all), up to " << particles << " particles per run.\n\n"
    << "## Caveats\n\n"
    << "- One angle cannot fix two parameters: many (sliding, rolling) friction pairs give the same angle "
    << "(Roessler et al. 2019). With one parameter searched, the others keep the materials file's values.\n"
    << "- A run's angle scatters with the random fill (see the seed spread); a match within the tolerance with one "
    << "seed is a match to within that scatter too.\n"
    << "- At " << s.scale_factor << "x the pipe is only a few particle lengths wide; see docs/scaling.md for when a "
    << "scaled AOR test is valid.\n";
  return m.str();
}

}  // namespace

int run_calibrate(const CalibrateOptions& opt) {
  const auto t_start = std::chrono::steady_clock::now();
  CalibrationStudy s = load_calibration_study(opt.study_file);
  select_cases(s, opt.cases);
  const std::string out = opt.output_override.empty() ? s.output_directory : opt.output_override;
  fs::create_directories(fs::path(out) / "inputs");
  fs::copy_file(opt.study_file, fs::path(out) / "inputs" / fs::path(opt.study_file).filename(),
                fs::copy_options::overwrite_existing);
  fs::copy_file(s.materials_file, fs::path(out) / "inputs" / fs::path(s.materials_file).filename(),
                fs::copy_options::overwrite_existing);
  std::ofstream study_log(fs::path(out) / "log.txt", std::ios::app);
  auto say = [&](const std::string& line) {
    std::cerr << "[calibrate] " << line << "\n";
    study_log << line << "\n" << std::flush;
  };
  std::string case_names;
  for (const CalibrationCase& c : s.cases) case_names += (case_names.empty() ? "" : ", ") + c.name;
  say("grainscale " + std::string(version) + " (" + git_revision + "), study " + opt.study_file + ", output " + out +
      ", cases " + case_names);

  // The materials at the run's scale (docs/scaling.md); the searched values are set on top.
  const dem::MaterialTable scaled = dem::scale_materials(dem::MaterialTable::load(s.materials_file), s.scaling);
  std::vector<RunRow> rows;
  std::vector<CaseOutcome> outcomes;
  bool all_converged = true;
  for (const CalibrationCase& c : s.cases) {
    CaseOutcome o;
    o.c = &c;
    const CalibrationParameter& first = c.parameters.front();
    // Start from a previous calibration if the study records one, else from the materials file.
    const double v0 = c.calibrated.empty() ? pair_property(scaled, first.pair, first.property, s.file) : c.calibrated[0];
    SearchSettings ss;
    ss.target = c.target_deg;
    ss.tolerance = s.tolerance_deg;
    ss.max_runs = s.max_runs;
    ss.start = std::clamp((v0 - first.lo) / (first.hi - first.lo), 0.0, 1.0);
    auto values_at = [&](double t) {
      std::vector<double> v;
      for (const CalibrationParameter& p : c.parameters) v.push_back(p.lo + t * (p.hi - p.lo));
      return v;
    };
    auto table_at = [&](const std::vector<double>& v) {
      dem::MaterialTable t = scaled;
      for (std::size_t k = 0; k < v.size(); ++k) set_pair_property(t, c.parameters[k].pair, c.parameters[k].property, v[k], s.file);
      return t;
    };
    auto angle_at = [&](double t) {
      PointSummary ps;
      ps.t = t;
      ps.values = values_at(t);
      const dem::MaterialTable table = table_at(ps.values);
      const int point = static_cast<int>(o.points.size()) + 1;
      std::vector<double> angles, sides, spreads;
      for (std::uint64_t seed : s.seeds) {
        char name[64];
        std::snprintf(name, sizeof name, "run_%02d_seed_%llu", point, static_cast<unsigned long long>(seed));
        const fs::path dir = fs::absolute(fs::path(out) / c.name / name);
        fs::create_directories(dir);
        std::ostringstream header;
        header << "materials of calibration study " << s.name << ", case " << c.name << ", point " << point
               << " (run scale " << s.scale_factor << "x, rolling rule " << dem::rolling_friction_rule_name(s.scaling.rolling)
               << ")\nfrom " << s.materials_file << "; searched:";
        for (std::size_t k = 0; k < ps.values.size(); ++k) header << " " << c.parameters[k].label() << " = " << ps.values[k];
        dem::write_file_atomically((dir / "materials.yaml").string(), materials_yaml(table, header.str()));
        const AorCase a = aor_case(s, c, seed, (dir / "materials.yaml").string());
        const std::string scenario = (dir / "scenario.yaml").string();
        dem::write_file_atomically(scenario, aor_scenario_yaml(a, dir.string()));
        std::ofstream run_log(dir / "log.txt");
        auto log = [&](const std::string& line) {
          std::cerr << "[calibrate " << c.name << " " << point << "/" << seed << "] " << line << "\n";
          run_log << line << "\n" << std::flush;
        };
        std::ostringstream what;
        what << "case " << c.name << ", point " << point << ", seed " << seed << ":";
        for (std::size_t k = 0; k < ps.values.size(); ++k) what << " " << c.parameters[k].label() << " = " << ps.values[k];
        say(what.str());
        RunRow row;
        row.case_name = c.name, row.point = point, row.seed = seed, row.values = ps.values;
        const auto t0 = std::chrono::steady_clock::now();
        try {
          row.r = run_aor(scenario, a, (dir / "final.h5").string(), log);
          row.ok = true;
          draw_pile_profile(row.r.angle, c.name + ", point " + std::to_string(point) + ", seed " + std::to_string(seed))
              .write_png((dir / "profile.png").string());
          angles.push_back(row.r.angle.mean_deg);
          sides.push_back(row.r.angle.side_mean_deg);
          spreads.push_back(row.r.angle.spread_deg);
        } catch (const dem::BlowUp& e) {
          row.error = std::string("blew up: ") + e.what();
        } catch (const std::invalid_argument& e) {
          row.error = std::string("no angle: ") + e.what();
        }
        row.r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!row.ok) log("error: " + row.error);
        say("  -> " + (row.ok ? fixed(row.r.angle.mean_deg, 2) + " +- " + fixed(row.r.angle.spread_deg, 2) +
                                    " deg (side " + fixed(row.r.angle.side_mean_deg, 2) + "), " +
                                    fixed(row.r.wall_seconds / 60, 1) + " min"
                              : row.error));
        rows.push_back(row);
        dem::write_file_atomically((fs::path(out) / "runs.csv").string(), csv(rows, s));
      }
      if (angles.size() == s.seeds.size()) {
        double sum = 0, sum2 = 0, side = 0, spread = 0;
        for (std::size_t i = 0; i < angles.size(); ++i) sum += angles[i], sum2 += angles[i] * angles[i], side += sides[i], spread += spreads[i];
        const double n = static_cast<double>(angles.size());
        ps.angle = sum / n;
        ps.seed_spread = n > 1 ? std::sqrt(std::max(0.0, (sum2 - n * ps.angle * ps.angle) / (n - 1))) : 0.0;
        ps.side = side / n;
        ps.sector_spread = spread / n;
      }
      o.points.push_back(ps);
      return ps.angle;
    };
    o.search = bracketed_search(angle_at, ss);
    say("case " + c.name + ": " + o.search.status);
    all_converged = all_converged && o.search.converged;
    const double t_chosen = o.search.converged ? o.search.points[o.search.best].t : o.search.interpolated_t;
    o.chosen = values_at(t_chosen);
    o.chosen_verified = o.search.converged;
    if (o.search.best >= 0) o.chosen_angle = o.search.points[o.search.best].angle;

    // Calibrated materials and the sensitivity figure.
    std::ostringstream header;
    header << "Calibrated by `grainscale calibrate " << opt.study_file << "` (case " << c.name << "), grainscale " << version
           << " (" << git_revision << ")\nTarget angle of repose " << c.target_deg << " deg; "
           << (o.chosen_verified ? "verified by a run: " + fixed(o.chosen_angle, 2) + " deg"
                                 : "NOT verified by a run; closest run " + fixed(o.chosen_angle, 2) + " deg")
           << "\nValues hold at particle scale " << s.scale_factor << "x (rolling rule "
           << dem::rolling_friction_rule_name(s.scaling.rolling) << ", docs/scaling.md). Search: " << o.search.status << ".";
    o.materials_file = (fs::path(out) / (c.name + "_materials.yaml")).string();
    dem::write_file_atomically(o.materials_file, materials_yaml(table_at(o.chosen), header.str()));
    SensitivityFigure fig;
    fig.title = s.name + ": " + c.name + " (target " + fixed(c.target_deg, 2) + "°)";
    for (const auto& p : c.parameters) fig.parameters.push_back(p.label());
    for (const PointSummary& p : o.points) fig.points.push_back({p.values, p.angle, p.sector_spread});
    fig.target = c.target_deg;
    fig.tolerance = s.tolerance_deg;
    fig.chosen = o.chosen;
    o.png_file = (fs::path(out) / (c.name + "_sensitivity.png")).string();
    draw_sensitivity(fig).write_png(o.png_file);
    outcomes.push_back(o);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    dem::write_file_atomically((fs::path(out) / "report.md").string(), report_md(s, outcomes, rows, wall));
  }
  say("report: " + (fs::path(out) / "report.md").string());
  return all_converged ? 0 : 1;
}

int calibrate_main(const std::vector<std::string>& positional, const std::string& out, const std::string& threads,
                   const std::vector<std::string>& cases) {
  if (positional.size() != 1) {
    throw InputError("usage: grainscale calibrate STUDY.yaml [--out DIR] [--threads N] [--case NAME[,NAME...]]");
  }
  std::vector<std::string> names;  // --case a,b --case c
  for (const std::string& list : cases) {
    std::stringstream in(list);
    for (std::string n; std::getline(in, n, ',');) {
      if (n.empty()) throw InputError("--case '" + list + "': an empty case name");
      names.push_back(n);
    }
  }
  if (!threads.empty()) {
    omp_set_num_threads(thread_count_option(threads));
  }
  return run_calibrate({positional[0], out, names});
}

}  // namespace grainscale::studies
