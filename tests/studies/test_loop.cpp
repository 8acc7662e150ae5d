// `grainscale loop` on synthetic data: the continuum model itself, with an effect the fitted model
// lacks hidden in the data (surface drift), plus noise: the loop must rank that effect first, add it,
// and cut the held-out error; with no hidden effect it must add nothing. The residual diagnosis:
// white noise is judged white, a smooth structure is not; symmetric, antisymmetric and harmonic
// residuals land in their parts. Bad settings are InputErrors naming file and key.
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "continuum/settings.hpp"
#include "continuum/simulate.hpp"
#include "continuum/term_registry.hpp"
#include "dem/input_error.hpp"
#include "studies/loop_command.hpp"
#include "studies/loop_cg_fields.hpp"
#include "studies/loop_diagnosis.hpp"
#include "studies/loop_motion.hpp"

using namespace grainscale;
using namespace grainscale::studies;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("grainscale_test_loop_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// A 0.4 m bed, 0.08 m deep, with a convection cell; `extra` adds terms (the hidden truth).
std::string model_yaml(int nx, int nz, const std::string& extra = "") {
  std::ostringstream s;
  s << "grid: {length: 0.4, nx: " << nx << ", nz: " << nz << ", depth: 0.08}\n"
    << "flow: {type: cellular, amplitude: 4.0e-4, background_shear: 0.05}\n"
    << "terms:\n  advection: {limiter: van_leer}\n  segregation: {S: 1.0e-3}\n"
    << "  shear_diffusion: {C: 0.5, d: 4.0e-3}\n  background_diffusion: {D0: 2.0e-6}\n"
    << extra << "initial: {type: uniform, value: 0.15}\n"
    << "time: {end: 400, outputs: 1}\nintegrator: {method: ssp_rk3, cfl: 0.4}\n"
    << "observation: {kappa: 150, delta: 0.01}\noutput: {folder: unused}\n";
  return s.str();
}

/// Fields (every cell) and coverage (every column) of the truth at `times`, with Gaussian noise.
void write_data(const fs::path& dir, const std::string& truth_yaml, const std::vector<double>& times, double sigma,
                unsigned long seed) {
  write(dir / "truth.yaml", truth_yaml);
  const auto s = continuum::load_continuum_settings((dir / "truth.yaml").string());
  const continuum::Model m = continuum::build_model(s);
  continuum::IntegratorSettings accurate{"ssp_rk3"};
  accurate.cfl = 0.1;
  const auto fields = continuum::simulate(m, continuum::initial_field(s, m.grid()), 0, times, accurate);
  const continuum::SurfaceCoverage obs(s.kappa, s.delta);
  gsl_rng* rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  std::ostringstream f, c;
  f << "t_s,x_m,z_m,c\n";
  c << "t_s,x_m,coverage\n";
  const auto& g = m.grid();
  for (std::size_t j = 0; j < times.size(); ++j) {
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 0; k < g.nz(); ++k) {
        f << times[j] << "," << g.x_centre(i) << "," << g.z_centre(i, k) << ","
          << fields[j][g.index(i, k)] + gsl_ran_gaussian(rng, sigma) << "\n";
      }
    }
    const auto cov = obs.coverage(g, fields[j]);
    for (int i = 0; i < g.nx(); ++i) c << times[j] << "," << g.x_centre(i) << "," << cov[i] + gsl_ran_gaussian(rng, sigma) << "\n";
  }
  gsl_rng_free(rng);
  write(dir / "fields.csv", f.str());
  write(dir / "coverage.csv", c.str());
}

/// model.yaml (no hidden effect), fit.yaml (S and kappa) and loop.yaml.
void write_settings(const fs::path& dir, int nx, int nz, double sigma, const std::string& loop_extra = "") {
  write(dir / "model.yaml", model_yaml(nx, nz));
  std::ostringstream f;
  f << "model: model.yaml\ndata: {fields: fields.csv, field_sigma: " << sigma << ", coverage: coverage.csv, coverage_sigma: "
    << sigma << "}\nfit: {parameters: [S, kappa], start: {S: 1.5e-3, kappa: 100}, cfl: 0.8}\noutput: fit_out\n";
  write(dir / "fit.yaml", f.str());
  write(dir / "loop.yaml", "fit: fit.yaml\ncv: {by: time, blocks: 3}\ncandidate_iterations: 20\n" + loop_extra + "output: loop_out\n");
}

const std::vector<double> kTimes{50, 100, 150, 200, 250, 300};

}  // namespace

TEST_CASE("White noise is judged white and a smooth structure is not", "[studies][loop]") {
  gsl_rng* rng = gsl_rng_alloc(gsl_rng_mt19937);
  const continuum::Grid g = continuum::Grid::flat(0.4, 0.1, 20, 5);
  int white = 0;
  for (int rep = 0; rep < 10; ++rep) {
    gsl_rng_set(rng, 100 + rep);
    std::vector<ResidualPoint> noise, structured;
    for (int t = 0; t < 6; ++t) {
      for (int i = 0; i < g.nx(); ++i) {
        for (int k = 0; k < g.nz(); ++k) {
          ResidualPoint p;
          p.time = t;
          p.t = 10.0 * (t + 1);
          p.column = i;
          p.layer = k;
          p.x = g.x_centre(i);
          p.z = g.z_centre(i, k);
          p.r = gsl_ran_gaussian(rng, 1.0);
          p.model_c = 0.2;
          noise.push_back(p);
          p.r += 1.5 * std::sin(2 * M_PI * p.x / 0.4);  // a smooth structure of the size of the noise
          structured.push_back(p);
        }
      }
    }
    const Diagnosis a = diagnose(g, noise, {}), b = diagnose(g, structured, {});
    white += a.white;
    CHECK_FALSE(b.white);
    INFO(b.verdict);
  }
  CHECK(white >= 9);  // Bonferroni at alpha = 0.01: false alarms are rare
  gsl_rng_free(rng);
}

TEST_CASE("The diagnosis splits symmetric and antisymmetric and harmonic and surface and wall parts", "[studies][loop]") {
  const continuum::Grid g = continuum::Grid::flat(0.4, 0.1, 10, 4);
  auto points = [&](auto r_of) {
    std::vector<ResidualPoint> out;
    for (int t = 0; t < 12; ++t) {
      for (int i = 0; i < g.nx(); ++i) {
        for (int k = 0; k < g.nz(); ++k) {
          ResidualPoint p;
          p.time = t;
          p.t = 1.5 * t;
          p.column = i;
          p.layer = k;
          p.x = g.x_centre(i);
          p.z = g.z_centre(i, k);
          p.model_c = 0.1 * k;
          p.r = r_of(p);
          out.push_back(p);
        }
      }
    }
    return out;
  };
  DiagnosisSettings s;
  s.period = 18;
  s.surface_layer = 0.025;
  s.wall_band = 0.05;
  const Diagnosis sym = diagnose(g, points([](const ResidualPoint& p) { return std::cos(2 * M_PI * p.x / 0.4); }), s);
  CHECK(sym.symmetric_energy == Approx(1).margin(1e-12));
  const Diagnosis anti = diagnose(g, points([](const ResidualPoint& p) { return p.x - 0.2; }), s);
  CHECK(anti.antisymmetric_energy == Approx(1).margin(1e-12));
  const Diagnosis h1 = diagnose(g, points([](const ResidualPoint& p) { return std::sin(2 * M_PI * p.t / 18); }), s);
  REQUIRE(h1.harmonics_resolved);
  CHECK(h1.first_harmonic > 0.99);
  const Diagnosis h2 = diagnose(g, points([](const ResidualPoint& p) { return 0.3 + std::cos(4 * M_PI * p.t / 18); }), s);
  CHECK(h2.second_harmonic > 0.8);
  CHECK(h2.mean_energy > 0.05);
  // Residual only in the top layer and at the walls; growing with the model's c.
  const Diagnosis top = diagnose(g, points([](const ResidualPoint& p) { return p.layer == 3 ? 1.0 : 0.0; }), s);
  CHECK(top.regions[0].rms == Approx(1));
  CHECK(top.regions[1].rms == 0);
  CHECK(top.correlation_with_c > 0.7);
  const Diagnosis wall = diagnose(g, points([](const ResidualPoint& p) { return p.column == 0 || p.column == 9 ? 1.0 : 0.0; }), s);
  CHECK(wall.regions[3].rms == Approx(1));
  CHECK(wall.regions[4].rms == 0);
}

TEST_CASE("grainscale loop finds a hidden surface drift and adds it and cuts the held-out error", "[studies][loop]") {
  const fs::path dir = scratch("drift");
  const double sigma = 0.01;
  write_data(dir, model_yaml(10, 5, "  surface_drift: {U: 8.0e-4, thickness: 0.01}\n"), kTimes, sigma, 7);
  write_settings(dir, 10, 5, sigma);
  const LoopSettings s = load_loop_settings((dir / "loop.yaml").string());
  const LoopResult r = run_loop(s);
  REQUIRE(r.chosen >= 0);
  const Evaluation& e = r.candidates[r.chosen];
  CHECK(r.candidates.front().name == "surface_drift");
  CHECK(e.name == "surface_drift");
  INFO(r.reason);
  CHECK_FALSE(r.diagnosis_before.white);
  // Held-out error: lower overall, and its part beyond the noise at least halved.
  CHECK(e.cv_error < r.base.cv_error);
  CHECK(e.cv_model_error < 0.5 * r.base.cv_model_error);
  CHECK(r.diagnosis_after.white);
  // The fitted strength: within 3 standard errors of the truth.
  const double U = e.values.back(), se = e.standard_errors.back();
  INFO("U = " << U << " +- " << se);
  CHECK(std::abs(U - 8e-4) < 3 * se);
  CHECK(fs::exists(dir / "loop_out" / "report.md"));
  CHECK(fs::exists(dir / "loop_out" / "after_coverage.png"));
  CHECK(fs::exists(dir / "loop_out" / "before_autocorrelation.png"));
  fs::remove_all(dir);
}

TEST_CASE("grainscale loop adds nothing when the data hold no hidden effect", "[studies][loop]") {
  const fs::path dir = scratch("none");
  const double sigma = 0.01;
  write_data(dir, model_yaml(10, 5), kTimes, sigma, 11);
  write_settings(dir, 10, 5, sigma, "candidates: [surface_drift, wall_mobility, pause_creep]\n");
  const LoopResult r = run_loop(load_loop_settings((dir / "loop.yaml").string()));
  INFO(r.reason);
  CHECK(r.chosen < 0);
  CHECK(r.diagnosis_before.white);
  fs::remove_all(dir);
}

TEST_CASE("Bad loop settings are input errors naming the file and key", "[studies][loop]") {
  const fs::path dir = scratch("bad");
  write_data(dir, model_yaml(6, 3), {100, 200}, 0.01, 3);
  write_settings(dir, 6, 3, 0.01);
  auto fails_with = [&](const std::string& loop_yaml, const std::string& needle) {
    write(dir / "bad.yaml", loop_yaml);
    try {
      (void)load_loop_settings((dir / "bad.yaml").string());
      FAIL("no error for: " << loop_yaml);
    } catch (const InputError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(needle) != std::string::npos);
    }
  };
  fails_with("fit: nothing.yaml\noutput: o\n", "cannot find");
  fails_with("fit: fit.yaml\ncandidates: [no_such_effect]\noutput: o\n", "no_such_effect");
  fails_with("fit: fit.yaml\ncandidates: {surface_drift: {speed: 1}}\noutput: o\n", "speed");
  fails_with("fit: fit.yaml\ncandidates: {lever_arm: {axis_x: nope}}\noutput: o\n", "axis_x");
  fails_with("fit: fit.yaml\ncv: {blocks: 1}\noutput: o\n", "blocks");
  fails_with("fit: fit.yaml\ncv: {by: space}\noutput: o\n", "by");
  fails_with("fit: fit.yaml\ncontainer: box\noutput: o\n", "scenario");
  fails_with("fit: fit.yaml\nscenario: missing.yaml\noutput: o\n", "cannot find");
  fails_with("fit: fit.yaml\nselection: {min_cv_gain: 2}\noutput: o\n", "min_cv_gain");
  fails_with("fit: fit.yaml\nunknown_key: 1\noutput: o\n", "unknown_key");
  fails_with("fit: fit.yaml\n", "output");
  // A candidate the model already has.
  write(dir / "model2.yaml", model_yaml(6, 3, "  surface_drift: {U: 1.0e-5}\n"));
  write(dir / "fit2.yaml", "model: model2.yaml\ndata: {coverage: coverage.csv, coverage_sigma: 0.01}\nfit: {parameters: [kappa]}\noutput: f\n");
  fails_with("fit: fit2.yaml\ncandidates: [surface_drift]\noutput: o\n", "already has");
  // A bad data file surfaces as the fit's input error (file and line).
  write(dir / "coverage.csv", "t_s,x_m,coverage\n100,0.1,abc\n");
  CHECK_THROWS_AS(run_loop(load_loop_settings((dir / "loop.yaml").string())), InputError);
  fs::remove_all(dir);
}

namespace {

struct Hidden {
  std::string candidate;    // what the loop should name
  std::string truth_terms;  // added to the truth's terms ("" for none)
  double delta = 0.01;      // the truth's visible depth (the model assumes 0.01)
  double strength = 0;      // the true value of the candidate's fitted parameter
};

}  // namespace

TEST_CASE("Each hidden library effect is found in 9 of 10 noisy replicates and none is added without one",
          "[.validate][studies]") {
  // Strengths: large enough to matter over the 300 s of data at sigma = 0.01, in the physical range
  // of docs/loop.md. lever_arm uses a ship-hold geometry (axis 15 m away): in the report's box the
  // lever arm is too weak to see (a/g ~ 0.002).
  const std::vector<Hidden> cases{
      {"surface_drift", "  surface_drift: {U: 8.0e-4}\n", 0.01, 8e-4},
      {"lever_arm", "  lever_arm: {S: 0.05, omega2: 0.02, axis_x: -15, axis_z: -5}\n", 0.01, 0.05},
      {"concentration_segregation", "  concentration_segregation: {S: 3.0e-3}\n", 0.01, 3e-3},
      {"clustering_diffusion", "  clustering_diffusion: {C: 20}\n", 0.01, 20},
      {"wall_mobility", "  wall_mobility: {W: 3.0e-4}\n", 0.01, 3e-4},
      {"pause_creep", "  pause_creep: {V: 2.0e-4}\n", 0.01, 2e-4},
      {"observation_depth", "", 0.04, 0.04},
      {"none", "", 0.01, 0},
  };
  const std::string candidates =
      "candidates: {lever_arm: {omega2: 0.02, axis_x: -15, axis_z: -5}, surface_drift: {}, concentration_segregation: {},"
      " clustering_diffusion: {}, wall_mobility: {}, pause_creep: {}, observation_depth: {}}\n";
  std::ostringstream table;
  table << "| hidden | found (of 10) | strength within 95 % CI (of found) | mean fitted +- mean SE | CV error base -> after |\n";
  // GRAINSCALE_LOOP_CASES=a,b runs only those (the whole table takes about 16 min).
  const char* only = std::getenv("GRAINSCALE_LOOP_CASES");
  for (const Hidden& h : cases) {
    if (only && std::string(",") .append(only).append(",").find("," + h.candidate + ",") == std::string::npos) continue;
    int found = 0, covered = 0;
    double sum_v = 0, sum_se = 0, cv0 = 0, cv1 = 0;
    for (int rep = 0; rep < 10; ++rep) {
      const fs::path dir = scratch("validate_" + h.candidate + std::to_string(rep));
      std::string truth = model_yaml(10, 5, h.truth_terms);
      if (h.delta != 0.01) truth.replace(truth.find("delta: 0.01"), 11, "delta: " + std::to_string(h.delta));  // the truth sees deeper
      write_data(dir, truth, kTimes, 0.01, 1000 + 17 * rep);
      write_settings(dir, 10, 5, 0.01, candidates);
      const LoopResult r = run_loop(load_loop_settings((dir / "loop.yaml").string()));
      const std::string chosen = r.chosen >= 0 ? r.candidates[r.chosen].name : "none";
      cv0 += r.base.cv_error / 10;
      cv1 += (r.chosen >= 0 ? r.candidates[r.chosen].cv_error : r.base.cv_error) / 10;
      if (chosen == h.candidate) {
        ++found;
        if (r.chosen >= 0) {
          const double v = r.candidates[r.chosen].values.back(), se = r.candidates[r.chosen].standard_errors.back();
          covered += std::abs(v - h.strength) < 1.96 * se;
          sum_v += v;
          sum_se += se;
        }
      }
      std::cout << h.candidate << " replicate " << rep << ": chose " << chosen << "\n";
      fs::remove_all(dir);
    }
    table << "| " << h.candidate << " | " << found << " | " << (h.candidate == "none" ? "-" : std::to_string(covered)) << " | "
          << (found && h.candidate != "none" ? std::to_string(sum_v / found) + " +- " + std::to_string(sum_se / found) : "-")
          << " | " << cv0 << " -> " << cv1 << " |\n";
    std::cout << table.str() << std::flush;
    CHECK(found >= 9);
  }
  std::cout << table.str();
}

TEST_CASE("Motion facts of the report's platform come from the DEM scenario", "[studies][loop]") {
  const MotionFacts f = motion_facts(std::string(GRAINSCALE_SOURCE_DIR) + "/studies/platform_box_demo.yaml", "box");
  CHECK(f.period == Approx(18));  // 1/f + 2 pauses
  CHECK(f.pause_fraction == Approx(8.0 / 18).margin(2e-3));
  // Transitions theta = A cos(pi t / h), h = 5 s, for 10 s of every 18: <omega^2> = A^2 pi^2 / (2 h^2) * 10/18.
  const double A = 24 * M_PI / 180;
  CHECK(f.omega2_mean == Approx(A * A * M_PI * M_PI / 50 * 10 / 18).epsilon(1e-3));
  CHECK(f.peak_angle_deg == Approx(24).epsilon(1e-3));
  CHECK(f.axis_x == Approx(-0.6));
  CHECK(f.axis_z == Approx(-0.3));
  CHECK_THROWS_AS(motion_facts(std::string(GRAINSCALE_SOURCE_DIR) + "/studies/platform_box_demo.yaml", "lid"), InputError);
}

TEST_CASE("A fields file that is not a grainscale cg HDF5 file is an input error", "[studies][loop]") {
  const fs::path dir = scratch("h5");
  write(dir / "fields.h5", "not hdf5");
  CHECK_THROWS_WITH(cg_fields_to_csv((dir / "fields.h5").string(), (dir / "out.csv").string()),
                    Catch::Contains("cannot open as HDF5"));
  fs::remove_all(dir);
}
