// `grainscale fit` end to end: synthetic data made by the model itself (sparse fields with their own
// sigma, coverage with a sigma key) are fitted back to the true coefficients within their standard
// errors; on complete, uniform data the fit agrees with continuum::fit; bad settings and data are
// InputErrors that name the file and what is wrong.
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "continuum/fit.hpp"
#include "continuum/settings.hpp"
#include "continuum/simulate.hpp"
#include "dem/input_error.hpp"
#include "studies/fit_command.hpp"
#include "studies/fit_observations.hpp"
#include "studies/observed_fit.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale;
using namespace grainscale::studies;
namespace fs = std::filesystem;

namespace {

const double kS = 1e-3, kC = 0.5, kD0 = 2e-6, kKappa = 150;

/// A 0.4 m bed with a sloping surface, a convection cell and all four terms at the true values.
std::string model_yaml(int nx, int nz) {
  std::ostringstream s;
  s << "grid: {length: 0.4, nx: " << nx << ", nz: " << nz << ", surface: [";
  for (int f = 0; f <= nx; ++f) s << (f ? ", " : "") << 0.1 * (1 + 0.2 * std::cos(M_PI * f / nx));
  s << "]}\n"
       "flow: {type: cellular, amplitude: 5.0e-4, background_shear: 0.05}\n"
       "terms:\n"
       "  advection: {limiter: van_leer}\n"
       "  segregation: {S: "
    << kS << ", limiter: van_leer}\n  shear_diffusion: {C: " << kC << ", d: 4.0e-3}\n  background_diffusion: {D0: " << kD0
    << "}\n"
       "initial: {type: layers, below: 0.3, above: 0.02, split: 0.5}\n"
       "time: {end: 400, outputs: 1}\n"
       "integrator: {method: ssp_rk3, cfl: 0.4}\n"
       "observation: {kappa: "
    << kKappa << ", delta: 0.01}\n"
       "output: {folder: unused}\n";
  return s.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// model.yaml (an nx x nz grid) in `dir`.
void write_model(const fs::path& dir, int nx = 16, int nz = 8) { write(dir / "model.yaml", model_yaml(nx, nz)); }

struct Truth {
  continuum::ContinuumSettings settings;
  std::unique_ptr<continuum::Model> model;
  std::vector<double> times;
  std::vector<std::vector<double>> fields;
};

Truth simulate_truth(const fs::path& dir, std::vector<double> times) {
  Truth t;
  t.settings = continuum::load_continuum_settings((dir / "model.yaml").string());
  t.model = std::make_unique<continuum::Model>(continuum::build_model(t.settings));
  continuum::IntegratorSettings accurate{"ssp_rk3"};
  accurate.cfl = 0.1;
  t.times = times;
  t.fields = continuum::simulate(*t.model, continuum::initial_field(t.settings, t.model->grid()), 0, times, accurate);
  return t;
}

}  // namespace

TEST_CASE("Fit data go to their nearest cell and combine by inverse variance", "[studies][fit]") {
  const continuum::Grid g(0.4, 4, 2, {0.1, 0.1, 0.1, 0.2, 0.2});  // column 2 is 0.15 deep, column 3 0.2
  // A fresh folder (mkdtemp), removed at the end even when a check fails.
  const grainscale::testing::TempDir tmp("test_fit_map");
  const fs::path& dir = tmp.path;
  write(dir / "f.csv",
        "t_s,x_m,z_m,c,sigma,extra\n"
        "10,0.05,0.01,0.2,0.1,7\n"   // column 0, layer 0
        "10,0.06,0.02,0.5,0.05,7\n"  // same cell: weights 100 and 400
        "10,0.25,0.10,0.4,0.1,7\n"   // column 2 (h 0.15): z/h = 0.67 -> layer 1
        "10,0.35,0.21,0.3,0.1,7\n"   // slightly above column 3's surface: its top layer
        "20,0.35,0.05,nan,0.1,7\n"   // no data
        "5,0.15,0.03,0.1,0.1,7\n");
  write(dir / "c.csv", "t_s,x_m,coverage\n20,0.39,0.6\n20,0.41,0.8\n");  // 0.41: beyond L but within half a column
  ObservationFiles files;
  files.fields = (dir / "f.csv").string();
  files.coverage = (dir / "c.csv").string();
  files.coverage_sigma = 0.05;
  const Observations o = map_observations(files, g, 0.0);
  CHECK(o.times == std::vector<double>{5, 10, 20});
  CHECK(o.field_rows == 5);
  REQUIRE(o.fields.size() == 4);
  // Sorted by (time, cell): t = 5 first.
  CHECK(o.fields[0].time == 0);
  CHECK(o.fields[0].index == g.index(1, 0));
  CHECK(o.fields[1].index == g.index(0, 0));
  CHECK(o.fields[1].points == 2);
  CHECK(o.fields[1].value == Approx((100 * 0.2 + 400 * 0.5) / 500));
  CHECK(o.fields[1].sigma == Approx(1 / std::sqrt(500.0)));
  CHECK(o.fields[2].index == g.index(2, 1));
  CHECK(o.fields[3].index == g.index(3, 1));
  REQUIRE(o.coverage.size() == 1);
  CHECK(o.coverage[0].index == 3);
  CHECK(o.coverage[0].value == Approx(0.7));
  CHECK(o.coverage[0].sigma == Approx(0.05 / std::sqrt(2.0)));
  CHECK(o.sigma_known);

  // Millimetres by mistake: outside the bed.
  write(dir / "mm.csv", "t_s,x_m,z_m,c\n10,50,10,0.2\n");
  files.fields = (dir / "mm.csv").string();
  files.field_sigma = 0.01;
  CHECK_THROWS_WITH(map_observations(files, g, 0.0), Catch::Contains("mm.csv:2") && Catch::Contains("outside the model bed"));
  // A time not after t0.
  write(dir / "t0.csv", "t_s,x_m,z_m,c\n0,0.1,0.01,0.2\n");
  files.fields = (dir / "t0.csv").string();
  CHECK_THROWS_WITH(map_observations(files, g, 0.0), Catch::Contains("t0.csv:2") && Catch::Contains("not after"));
  // Both kinds of data need a sigma each.
  write(dir / "ok.csv", "t_s,x_m,z_m,c\n10,0.1,0.01,0.2\n");
  files.fields = (dir / "ok.csv").string();
  files.field_sigma.reset();
  CHECK_THROWS_WITH(map_observations(files, g, 0.0), Catch::Contains("give each a sigma"));
  write(dir / "neg.csv", "t_s,x_m,z_m,c,sigma\n10,0.1,0.01,0.2,0\n");
  files.fields = (dir / "neg.csv").string();
  CHECK_THROWS_WITH(map_observations(files, g, 0.0), Catch::Contains("neg.csv:2: sigma must be positive"));

  // Rows above a bed's surface (a cg fields.csv's phi below min_solid_fraction) are not data.
  write(dir / "phi.csv", "t_s,x_m,z_m,c,phi\n10,0.05,0.01,0.2,0.55\n10,0.05,0.09,0.9,0.05\n10,0.15,0.09,0.3,0.3\n");
  files.fields = (dir / "phi.csv").string();
  files.field_sigma = 0.01;
  files.coverage.clear();
  files.min_solid_fraction = 0.3;
  const Observations bed = map_observations(files, g, 0.0);
  CHECK(bed.field_rows == 2);  // the 0.05 row is left out; 0.3 is kept
  REQUIRE(bed.fields.size() == 2);
  CHECK(bed.fields[0].value == 0.2);
  files.min_solid_fraction = 0;
  CHECK(map_observations(files, g, 0.0).field_rows == 3);
  // data.from: rows before it are not data (here all rows are at t = 10 s).
  files.from = 10;
  CHECK(map_observations(files, g, 0.0).field_rows == 3);
  files.from = 10.5;
  CHECK_THROWS_WITH(map_observations(files, g, 0.0), Catch::Contains("no finite values"));
  files.from = 0;
  files.min_solid_fraction = 0.3;
  files.fields = (dir / "ok.csv").string();  // no phi column
  CHECK_THROWS_WITH(map_observations(files, g, 0.0), Catch::Contains("ok.csv") && Catch::Contains("'phi' column"));
}

TEST_CASE("grainscale fit recovers S, C, D0 and kappa from sparse, noisy synthetic data", "[studies][fit]") {
  const grainscale::testing::TempDir tmp("test_fit_recovery");
  const fs::path& dir = tmp.path;
  write_model(dir);
  const Truth truth = simulate_truth(dir, {25, 50, 100, 200, 400});
  const continuum::Grid& g = truth.model->grid();
  continuum::SurfaceCoverage camera(kKappa, 0.01);
  gsl_rng* rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 2);
  std::ostringstream fields, coverage;
  fields << "t_s,x_m,z_m,c,sigma\n";
  coverage << "t_s,x_m,coverage\n";
  int row = 0;
  for (std::size_t n = 0; n < truth.times.size(); ++n) {
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 0; k < g.nz(); ++k) {
        if (++row % 5 == 0) continue;  // a fifth of the cells not observed
        // The upper half is measured less well: sigma 0.015 there, 0.01 below.
        const double sigma = g.sigma_centre(k) > 0.5 ? 0.015 : 0.01;
        fields << truth.times[n] << "," << g.x_centre(i) << "," << g.z_centre(i, k) << ","
               << truth.fields[n][g.index(i, k)] + gsl_ran_gaussian(rng, sigma) << "," << sigma << "\n";
      }
      if (i == 3) fields << truth.times[n] << "," << g.x_centre(i) << ",0.01,nan,0.01\n";  // no data: skipped
    }
    const auto cov = camera.coverage(g, truth.fields[n]);
    for (int i = 0; i < g.nx(); ++i) coverage << truth.times[n] << "," << g.x_centre(i) << "," << cov[i] + gsl_ran_gaussian(rng, 0.01) << "\n";
  }
  gsl_rng_free(rng);
  write(dir / "fields.csv", fields.str());
  write(dir / "coverage.csv", coverage.str());
  write(dir / "fit.yaml",
        "model: model.yaml\n"
        "data: {fields: fields.csv, coverage: coverage.csv, coverage_sigma: 0.01}\n"
        "fit:\n"
        "  parameters: [S, C, D0, kappa]\n"
        "  start: {S: 2.5e-3, C: 0.2, D0: 6.0e-6, kappa: 75}   # 2 to 3 times off\n"
        "output: out\n");

  const FitCommandSettings settings = load_fit_command_settings((dir / "fit.yaml").string());
  CHECK(settings.fit.parameters ==
        std::vector<std::string>{"segregation.S", "shear_diffusion.C", "background_diffusion.D0", "observation.kappa"});
  const FitCommandSummary sum = run_fit_command(settings);
  const continuum::FitResult& r = sum.result;
  const std::vector<double> truth_values{kS, kC, kD0, kKappa};
  const std::vector<double> max_relative_error{0.05, 0.4, 0.4, 0.05};  // C and D0 share the diffusivity (docs/continuum.md)
  std::ostringstream report;
  report << r.status << " after " << r.iterations << " iterations, chi2/dof = " << r.chi2 / r.dof << " (" << r.residuals
         << " observations)\n";
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    report << r.names[j] << " = " << r.values[j] << " +- " << r.standard_errors[j] << " (true " << truth_values[j] << ", off by "
           << (r.values[j] - truth_values[j]) / r.standard_errors[j] << " sigma)\n";
  }
  INFO(report.str());
  REQUIRE(r.converged);
  CHECK(sum.field_observations == 512);  // 5 times x 128 cells, a fifth left out
  CHECK(sum.coverage_observations == 80);
  CHECK(r.chi2 / r.dof == Approx(1).margin(0.15));
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    CHECK(std::abs(r.values[j] - truth_values[j]) < 3 * r.standard_errors[j]);
    CHECK(r.standard_errors[j] < max_relative_error[j] * truth_values[j]);
  }

  // What was written: fit.yaml reads back, the report and the figures are there.
  const YAML::Node y = YAML::LoadFile((dir / "out" / "fit.yaml").string());
  CHECK(y["converged"].as<bool>());
  CHECK(y["parameters"]["segregation.S"]["value"].as<double>() == Approx(r.values[0]).epsilon(1e-9));
  CHECK(y["parameters"]["observation.kappa"]["standard_error"].as<double>() == Approx(r.standard_errors[3]).epsilon(1e-9));
  CHECK(y["parameters"]["segregation.S"]["unit"].as<std::string>() == "m");
  CHECK(y["correlation"].size() == 4);
  CHECK(y["correlation"][1][1].as<double>() == Approx(1));
  CHECK(y["chi2_per_dof"].as<double>() == Approx(r.chi2 / r.dof).epsilon(1e-9));
  CHECK(read(dir / "out" / "report.md").find("| `shear_diffusion.C` |") != std::string::npos);
  for (const char* png : {"fields_first.png", "fields_last.png", "coverage.png", "coverage_residual.png", "residuals.png"}) {
    INFO(png);
    CHECK(read(dir / "out" / png).substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
  }
}

TEST_CASE("On complete data with one sigma the fit agrees with continuum::fit", "[studies][fit]") {
  const grainscale::testing::TempDir tmp("test_fit_agree");
  const fs::path& dir = tmp.path;
  write_model(dir, 12, 6);
  const Truth truth = simulate_truth(dir, {50, 200});
  continuum::SurfaceCoverage camera(kKappa, 0.01);
  continuum::FitData data;
  data.c0 = continuum::initial_field(truth.settings, truth.model->grid());
  data.times = truth.times;
  data.field_sigma = 0.01;
  data.coverage_sigma = 0.02;
  gsl_rng* rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  for (const auto& f : truth.fields) {
    auto c = f;
    for (double& v : c) v += gsl_ran_gaussian(rng, 0.01);
    auto cov = camera.coverage(truth.model->grid(), f);
    for (double& v : cov) v += gsl_ran_gaussian(rng, 0.02);
    data.fields.push_back(c);
    data.coverage.push_back(cov);
  }
  gsl_rng_free(rng);
  // The same data as observations: every cell and column once, in the same order of residuals
  // does not matter for least squares.
  const continuum::Grid& g = truth.model->grid();
  Observations obs;
  obs.times = data.times;
  for (std::size_t n = 0; n < data.times.size(); ++n) {
    for (std::size_t m = 0; m < g.cells(); ++m) obs.fields.push_back({n, m, data.fields[n][m], 0.01, 1});
    for (int i = 0; i < g.nx(); ++i) obs.coverage.push_back({n, static_cast<std::size_t>(i), data.coverage[n][i], 0.02, 1});
  }
  continuum::FitSettings settings;
  settings.parameters = {"segregation.S", "observation.kappa"};
  continuum::Model a = continuum::build_model(truth.settings), b = continuum::build_model(truth.settings);
  a.set_parameter("segregation.S", 2e-3);
  b.set_parameter("segregation.S", 2e-3);
  continuum::SurfaceCoverage oa(100, 0.01), ob(100, 0.01);
  const continuum::FitResult ra = continuum::fit(a, oa, data, settings);
  const continuum::FitResult rb = fit_observations(b, ob, ModelStart{data.c0, 0, {}}, obs, settings);
  REQUIRE(ra.converged);
  REQUIRE(rb.converged);
  CHECK(rb.chi2 == Approx(ra.chi2).epsilon(1e-6));
  CHECK(rb.dof == ra.dof);
  for (std::size_t j = 0; j < 2; ++j) {
    CHECK(rb.values[j] == Approx(ra.values[j]).epsilon(1e-6));
    CHECK(rb.standard_errors[j] == Approx(ra.standard_errors[j]).epsilon(1e-4));
  }
}

TEST_CASE("A parameter the data cannot see is flagged, not reported as fitted", "[studies][fit]") {
  // Fields 0.1 s after the start: background diffusion (D0 = 2e-6 m^2/s) has moved nothing yet.
  const grainscale::testing::TempDir tmp("test_fit_unseen");
  const fs::path& dir = tmp.path;
  write_model(dir, 12, 6);
  const Truth truth = simulate_truth(dir, {0.1});
  const continuum::Grid& g = truth.model->grid();
  std::ostringstream fields;
  fields << "t_s,x_m,z_m,c\n";
  for (int i = 0; i < g.nx(); ++i)
    for (int k = 0; k < g.nz(); ++k) fields << 0.1 << "," << g.x_centre(i) << "," << g.z_centre(i, k) << "," << truth.fields[0][g.index(i, k)] << "\n";
  write(dir / "fields.csv", fields.str());
  write(dir / "fit.yaml", "model: model.yaml\ndata: {fields: fields.csv, field_sigma: 0.01}\nfit: {parameters: [D0], start: {D0: 1.0e-5}}\noutput: out\n");
  const FitCommandSummary sum = run_fit_command(load_fit_command_settings((dir / "fit.yaml").string()));
  INFO(sum.result.names[0] << " = " << sum.result.values[0] << " +- " << sum.result.standard_errors[0]);
  REQUIRE(!sum.warnings.empty());
  CHECK(sum.warnings[0].find("background_diffusion.D0") != std::string::npos);
  CHECK(sum.warnings[0].find("constrain") != std::string::npos);
  CHECK(read(dir / "out" / "report.md").find("Do not use these values") != std::string::npos);
  CHECK(YAML::LoadFile((dir / "out" / "fit.yaml").string())["warnings"].size() == sum.warnings.size());
}

TEST_CASE("Bad fit settings and data are input errors naming what is wrong", "[studies][fit]") {
  const grainscale::testing::TempDir tmp("test_fit_bad");
  const fs::path& dir = tmp.path;
  write_model(dir, 12, 6);
  write(dir / "fields.csv", "t_s,x_m,z_m,c\n100,0.1,0.02,0.2\n100,0.2,0.05,0.1\n100,0.3,0.05,0.1\n");
  write(dir / "coverage.csv", "t_s,x_m,coverage,sigma\n100,0.1,0.3,0.01\n");
  auto settings = [&](const std::string& data, const std::string& fit, const std::string& extra = "") {
    write(dir / "fit.yaml", "model: model.yaml\ndata: " + data + "\nfit: " + fit + "\noutput: out\n" + extra);
    return (dir / "fit.yaml").string();
  };
  auto run = [&](const std::string& data, const std::string& fit) {
    run_fit_command(load_fit_command_settings(settings(data, fit)));
  };
  const std::string ok_data = "{fields: fields.csv, field_sigma: 0.01}";

  // Unknown parameter, with the allowed names listed.
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [S, friction]}")),
                    Catch::Contains("fit.yaml:3") && Catch::Contains("'friction' is not allowed") &&
                        Catch::Contains("segregation.S"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [S, segregation.S]}")),
                    Catch::Contains("listed twice"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: []}")), Catch::Contains("list the parameters"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [kappa]}")),
                    Catch::Contains("only through coverage data"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [S], maxiter: 5}")),
                    Catch::Contains("maxiter"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [S], start: {C: 0.1}}")),
                    Catch::Contains("'C' is not among the fitted parameters"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [C], start: {C: 20}}")),
                    Catch::Contains("admissible range"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [S], cfl: 2}")), Catch::Contains("cfl"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings("{}", "{parameters: [S]}")), Catch::Contains("give 'fields'"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings("{fields: fields.csv, min_solid_fraction: 1.5}", "{parameters: [S]}")),
                    Catch::Contains("data.min_solid_fraction"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings("{coverage: coverage.csv, min_solid_fraction: 0.3}", "{parameters: [kappa]}")),
                    Catch::Contains("fields' data only"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings("{fields: nowhere.csv}", "{parameters: [S]}")),
                    Catch::Contains("cannot find") && Catch::Contains("nowhere.csv"));
  CHECK_THROWS_WITH(load_fit_command_settings(settings(ok_data, "{parameters: [S]}", "colour: red\n")),
                    Catch::Contains("colour"));
  write(dir / "inline.yaml", "model: {grid: {length: 1}}\ndata: {fields: fields.csv}\nfit: {parameters: [S]}\noutput: out\n");
  CHECK_THROWS_WITH(load_fit_command_settings((dir / "inline.yaml").string()), Catch::Contains("as a file name"));

  // Data: a missing column, a value that is not a number.
  write(dir / "nocol.csv", "t_s,x_m,z_m,conc\n100,0.1,0.02,0.2\n");
  CHECK_THROWS_WITH(run("{fields: nocol.csv, field_sigma: 0.01}", "{parameters: [S]}"),
                    Catch::Contains("nocol.csv") && Catch::Contains("no column 'c'"));
  write(dir / "text.csv", "t_s,x_m,z_m,c\n100,0.1,0.02,0.2\n100,0.2,0.05,high\n");
  CHECK_THROWS_WITH(run("{fields: text.csv, field_sigma: 0.01}", "{parameters: [S]}"),
                    Catch::Contains("text.csv:3") && Catch::Contains("'high' is not a number"));
  // Fewer observations than parameters.
  CHECK_THROWS_WITH(run("{coverage: coverage.csv}", "{parameters: [S, kappa]}"), Catch::Contains("1 observations for 2"));
  CHECK_THROWS_AS(fit_command({}, ""), InputError);
}
