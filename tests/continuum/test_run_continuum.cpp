// The driver: a YAML run writes its HDF5 and CSV output with chaff conserved; every kind of bad
// input is an InputError naming the file and the key; coarse-grained fields load from HDF5.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "continuum/analytic_flows.hpp"
#include "continuum/field_output.hpp"
#include "continuum/gridded_flow.hpp"
#include "continuum/h5_writer.hpp"
#include "continuum/run_continuum.hpp"
#include "dem/input_error.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::continuum;
namespace fs = std::filesystem;

namespace {

const char* kGood = R"(grid: {length: 0.4, nx: 24, nz: 8, depth: 0.1}
flow: {type: cellular, amplitude: 5.0e-4, background_shear: 0.05}
terms:
  advection: {limiter: van_leer}
  segregation: {S: 1.0e-3, limiter: van_leer}
  shear_diffusion: {C: 0.5, d: 4.0e-3}
  background_diffusion: {D0: 1.0e-6}
initial: {type: layers, below: 0.3, above: 0.0, split: 0.5}
time: {end: 120, outputs: 4, stops: [45]}
integrator: {method: cvode, rtol: 1.0e-7, atol: 1.0e-10}
observation: {kappa: 150, delta: 0.01}
output: {folder: out, slice_width: 0.05}
)";

std::string write(const fs::path& dir, const std::string& text) {
  const fs::path file = dir / "run.yaml";
  std::ofstream(file) << text;
  return file.string();
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

std::vector<std::string> csv_row(const std::string& file, int row) {
  std::ifstream in(file);
  std::string line;
  int r = -1;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (++r == row) break;
  }
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  return cells;
}

}  // namespace

TEST_CASE("A YAML run writes versioned HDF5 and CSV output and conserves chaff", "[continuum][driver]") {
  const grainscale::testing::TempDir tmp("continuum_good");  // a fresh folder, removed at the end: parallel ctest processes cannot race
  const fs::path& dir = tmp.path;
  const ContinuumSettings settings = load_continuum_settings(write(dir, kGood));
  const ContinuumRunSummary r = run_continuum(settings);
  REQUIRE(fs::exists(r.h5_file));
  REQUIRE(fs::exists(r.slices_file));
  REQUIRE(fs::exists(r.coverage_file));
  REQUIRE_FALSE(fs::exists(r.h5_file + ".tmp"));
  CHECK(r.chaff_initial == Approx(0.3 * 0.5 * 0.4 * 0.1).epsilon(1e-12));
  CHECK(std::abs(r.chaff_final - r.chaff_initial) < 1e-12 * r.chaff_initial);
  CHECK(r.c_min > -1e-6);
  CHECK(r.c_max < 1 + 1e-6);

  // HDF5: format version and shapes.
  const hid_t f = H5Fopen(r.h5_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  long version = 0;
  const hid_t a = H5Aopen(f, "format_version", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_LONG, &version);
  H5Aclose(a);
  CHECK(version == kContinuumFormatVersion);
  const hid_t c = H5Dopen2(f, "/c", H5P_DEFAULT);
  const hid_t space = H5Dget_space(c);
  hsize_t dims[3] = {0, 0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Sclose(space);
  H5Dclose(c);
  H5Fclose(f);
  CHECK(dims[0] == 5);  // t = 0 and 4 outputs
  CHECK(dims[1] == 24);
  CHECK(dims[2] == 8);

  // CSV: 8 slices of 50 mm whose sum is the total chaff, at the last output.
  const auto last = csv_row(r.slices_file, 5);
  REQUIRE(last.size() == 9);
  CHECK(std::stod(last[0]) == Approx(120));
  double sum = 0;
  for (std::size_t j = 1; j < last.size(); ++j) sum += std::stod(last[j]);
  CHECK(sum == Approx(r.chaff_final).epsilon(1e-8));
  // Chaff has risen: coverage at the end exceeds the initial (no chaff on top) coverage.
  const auto cov0 = csv_row(r.coverage_file, 1), cov_end = csv_row(r.coverage_file, 5);
  CHECK(std::stod(cov0[5]) == 0.0);
  CHECK(std::stod(cov_end[5]) > 0.05);
}

TEST_CASE("Bad continuum input throws InputError naming file and key", "[continuum][driver][input]") {
  struct Bad {
    const char* from;
    const char* to;
    const char* expect;  // part of the message
  };
  const Bad bad = GENERATE(Bad{"nx: 24", "nx: 0", "grid.nx"}, Bad{"nx: 24, nz: 8", "nx: 100000, nz: 10000", "nx * nz"},
                           Bad{"S: 1.0e-3", "S: 5", "terms.segregation.S"},
                           Bad{"C: 0.5", "C: 0.5, c: 1", "terms.shear_diffusion.c"},
                           Bad{"limiter: van_leer}\n  seg", "limiter: superbee}\n  seg", "superbee"},
                           Bad{"background_diffusion:", "background_difusion:", "background_difusion"},
                           Bad{"below: 0.3", "below: 1.3", "initial.below"}, Bad{"end: 120", "end: -1", "time.end"},
                           Bad{"stops: [45]", "stops: [450]", "time.stops"},
                           Bad{"method: cvode", "method: euler", "integrator.method"},
                           Bad{"depth: 0.1}", "depth: 0.1, surface: [1]}", "depth"},
                           Bad{"type: cellular, amplitude: 5.0e-4, background_shear: 0.05", "type: file, file: missing.h5", "missing.h5"},
                           Bad{"background_shear: 0.05", "background_shear: 0.05, amplitud: 1", "flow.amplitud"},
                           Bad{"kappa: 150", "kapa: 150", "observation"},
                           Bad{"grid:", "model: {type: two_layer}\ngrid:", "model.type"},
                           Bad{"grid:", "model: {type: depth_averaged, n: 3}\ngrid:", "model.n"},
                           Bad{"grid:", "model: {type: resolved, cycle_average: {period: 2}}\ngrid:", "model.cycle_average"},
                           Bad{"grid:", "model: {type: depth_averaged, cycle_average: {period: 0}}\ngrid:", "model.cycle_average.period"},
                           Bad{"type: cellular, amplitude: 5.0e-4, background_shear: 0.05", "type: sloshing, amplitude: 0.2, period: 2", "flow.amplitude"},
                           Bad{"type: cellular, amplitude: 5.0e-4, background_shear: 0.05", "type: sloshing, amplitude: 0.01", "flow.period"},
                           Bad{"type: cellular, amplitude: 5.0e-4, background_shear: 0.05", "type: sloshing, amplitude: 0.01, period: 2, exponent: 1.5", "flow.exponent"});
  const grainscale::testing::TempDir tmp("continuum_bad");
  const fs::path& dir = tmp.path;
  const std::string file = write(dir, replaced(kGood, bad.from, bad.to));
  INFO("replacing '" << bad.from << "' by '" << bad.to << "'");
  try {
    (void)load_continuum_settings(file);
    FAIL("no InputError");
  } catch (const grainscale::InputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find(bad.expect) != std::string::npos);
    CHECK(what.find("run.yaml") != std::string::npos);
  }
}

TEST_CASE("A YAML run with a sloshing surface writes the surface per output and conserves chaff", "[continuum][driver][moving]") {
  const grainscale::testing::TempDir tmp("continuum_sloshing");
  const fs::path& dir = tmp.path;
  std::string text = replaced(kGood, "type: cellular, amplitude: 5.0e-4, background_shear: 0.05",
                              "type: sloshing, amplitude: 0.01, period: 4.0, cell: 3.0e-4, background_shear: 0.05");
  text = replaced(text, "end: 120, outputs: 4, stops: [45]", "end: 13, outputs: 4");  // t = 13 s: h ≠ H
  const ContinuumRunSummary r = run_continuum(load_continuum_settings(write(dir, text)));
  CHECK(std::abs(r.chaff_final - r.chaff_initial) < 1e-12 * r.chaff_initial);
  CHECK(r.c_min > -1e-6);
  CHECK(r.c_max < 1 + 1e-6);
  const hid_t f = H5Fopen(r.h5_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  std::vector<double> h(5 * 25);
  const hid_t set = H5Dopen2(f, "/surface_height", H5P_DEFAULT);
  REQUIRE(set >= 0);
  H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, h.data());
  H5Dclose(set);
  H5Fclose(f);
  CHECK(h[0] == Approx(0.1));                                          // t = 0, x = 0: at rest
  CHECK(h[4 * 25] == Approx(0.1 + 0.01 * std::sin(2 * std::numbers::pi * 13 / 4.0)));  // t = 13 s, x = 0
  // The slices still add up to the chaff on the moving grid.
  const auto last = csv_row(r.slices_file, 5);
  double sum = 0;
  for (std::size_t j = 1; j < last.size(); ++j) sum += std::stod(last[j]);
  CHECK(sum == Approx(r.chaff_final).epsilon(1e-8));
}

TEST_CASE("A YAML run of the depth-averaged model", "[continuum][driver][depth_averaged]") {
  const grainscale::testing::TempDir tmp("continuum_depth_averaged");
  const fs::path& dir = tmp.path;
  const std::string text = "model: {type: depth_averaged}\n" + std::string(kGood);
  const ContinuumSettings s = load_continuum_settings(write(dir, text));
  CHECK(s.closure == Closure::depth_averaged);
  const ContinuumRunSummary r = run_continuum(s);
  CHECK(r.chaff_initial == Approx(0.3 * 0.5 * 0.4 * 0.1).epsilon(1e-12));
  CHECK(std::abs(r.chaff_final - r.chaff_initial) < 1e-12 * r.chaff_initial);
  // The profile puts the chaff on top at once: coverage at t = 0 (the equilibrium of the initial
  // inventory) is already large.
  CHECK(std::stod(csv_row(r.coverage_file, 1)[5]) > 0.05);
  // Cycle averaging is read and reaches the model.
  const ContinuumSettings cyc = load_continuum_settings(
      write(dir, replaced(text, "model: {type: depth_averaged}", "model: {type: depth_averaged, cycle_average: {period: 2.0, phases: 8}}")));
  CHECK(cyc.cycle_phases == 8);
  CHECK(cyc.cycle_period == 2.0);
  const ContinuumRunSummary rc = run_continuum(cyc);
  CHECK(std::abs(rc.chaff_final - rc.chaff_initial) < 1e-12 * rc.chaff_initial);
  // A term without a depth-averaged form is refused, naming the file and the term.
  const std::string bad = replaced(text, "  background_diffusion: {D0: 1.0e-6}\n",
                                   "  background_diffusion: {D0: 1.0e-6}\n  surface_drift: {U: 1.0e-4, thickness: 0.01}\n");
  try {
    (void)load_continuum_settings(write(dir, bad));
    FAIL("no InputError");
  } catch (const grainscale::InputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("terms.surface_drift") != std::string::npos);
    CHECK(what.find("run.yaml") != std::string::npos);
  }
}

TEST_CASE("Coarse-grained fields from HDF5 give the flow they sample", "[continuum][driver][fields]") {
  // Sample the convection cell on a 40 × 20 data grid (cell centres), write the documented layout,
  // read it back: ψ rebuilt from u by (G1) matches the cell's ψ to the data resolution.
  constexpr double pi = std::numbers::pi;
  const double L = 0.4, H = 0.1, A = 5e-4;
  const int nxd = 40, nzd = 20;
  std::vector<double> x(nxd), z(nzd), u(nxd * nzd), rate(nxd * nzd), h(nxd, H);
  for (int j = 0; j < nxd; ++j) x[j] = (j + 0.5) * L / nxd;
  for (int k = 0; k < nzd; ++k) z[k] = (k + 0.5) * H / nzd;
  for (int k = 0; k < nzd; ++k) {
    for (int j = 0; j < nxd; ++j) {
      u[k * nxd + j] = A * pi / H * std::sin(pi * x[j] / L) * std::cos(pi * z[k] / H);
      rate[k * nxd + j] = 0.3;
    }
  }
  const grainscale::testing::TempDir tmp("continuum_fields");
  const fs::path& dir = tmp.path;
  const std::string file = (dir / "fields.h5").string();
  {
    H5Writer w(file);
    w.dataset("/x", {nxd}, x);
    w.dataset("/z", {nzd}, z);
    w.dataset("/u", {nzd, nxd}, u);
    w.dataset("/shear_rate", {nzd, nxd}, rate);
    w.dataset("/surface_height", {nxd}, h);
    w.close();
  }
  const GriddedFlow flow = GriddedFlow::load(file, L);
  const CellularFlow exact(A, L, [&](double) { return H; });
  double worst = 0;
  for (double xx : {0.1, 0.2, 0.3}) {
    for (double zz : {0.0, 0.03, 0.05, 0.08, 0.1}) {
      worst = std::max(worst, std::abs(flow.stream_function(xx, zz, 0) - exact.stream_function(xx, zz, 0)));
    }
  }
  INFO("max |ψ − ψ_exact| = " << worst << " of " << A);
  CHECK(worst < 0.02 * A);
  CHECK(flow.stream_function(0.2, H, 0) == Approx(0).margin(1e-15));  // no flow through the surface
  CHECK(flow.stream_function(0.0, 0.05, 0) == 0);                     // nor through the walls
  CHECK(flow.shear_rate(0.2, 0.05, 0) == Approx(0.3));

  // And a run driven by the file, with the surface taken from it.
  std::string text = replaced(kGood, "type: cellular, amplitude: 5.0e-4, background_shear: 0.05", "type: file, file: fields.h5");
  text = replaced(text, ", depth: 0.1}", "}");
  std::ofstream(dir / "run.yaml") << text;
  const ContinuumRunSummary r = run_continuum(load_continuum_settings((dir / "run.yaml").string()));
  CHECK(std::abs(r.chaff_final - r.chaff_initial) < 1e-12 * r.chaff_initial);
}
