// Phase-resolved flow input (phase_resolved_flow.hpp): a synthetic coarse-graining field file with
// one phase-averaged frame per phase bin, sampled from the sloshing standing wave
// (analytic_flows.hpp), is read back as a flow that interpolates in space and in phase, moves its
// surface, obeys the kinematic condition, is periodic, and drives the model with chaff conserved.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "hdf5_writer_fixture.hpp"
#include "bed_fixture.hpp"
#include "continuum/integrator.hpp"
#include "continuum/phase_resolved_flow.hpp"
#include "continuum/run_continuum.hpp"
#include "dem/input_error.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;
using Catch::Matchers::Contains;

namespace {

using grainscale::testing::attribute;
using grainscale::testing::dataset;

constexpr double pi = std::numbers::pi;

SloshingFlow::Shape shape() {
  SloshingFlow::Shape s;
  s.length = 0.4;
  s.depth = 0.1;
  s.amplitude = 0.015;
  s.period = 2.0;
  s.exponent = 2;
  s.cell = 2e-4;
  s.background_shear = 0.05;
  return s;
}

/// A cg field file (docs/coarsegrain_layout.md, 2-D grid 40 × 30 cells over 0.4 m × 0.15 m) with
/// `bins` phase-averaged frames of the sloshing flow, plus one snapshot frame (not a phase average)
/// and one empty phase bin, both of which the reader must skip. Written to `path`, which is returned.
std::string write_phase_file(const SloshingFlow& flow, int bins, const std::string& path) {
  const int nx = 40, nz = 30;
  const double L = 0.4, Z = 0.15, T = flow.shape().period;
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  attribute(f, "cg_layout_version", 1);
  const hid_t grid = H5Gcreate2(f, "grid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  attribute(grid, "dimension", 2);
  std::vector<double> x(nx), z(nz);
  for (int j = 0; j < nx; ++j) x[j] = L * (j + 0.5) / nx;
  for (int k = 0; k < nz; ++k) z[k] = Z * (k + 0.5) / nz;
  dataset(grid, "x", {static_cast<hsize_t>(nx)}, x);
  dataset(grid, "z", {static_cast<hsize_t>(nz)}, z);
  H5Gclose(grid);
  const hid_t frames = H5Gcreate2(f, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const int count = bins + 2;
  attribute(frames, "count", count);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int n = 0; n < count; ++n) {
    char group[16];
    std::snprintf(group, sizeof group, "%06d", n);
    const hid_t one = H5Gcreate2(frames, group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    // Frame 0: a plain snapshot; the last frame: an empty bin; the others: bins in reverse order.
    const int bin = n == 0 || n == count - 1 ? -1 : bins - n;
    const double lo = bin >= 0 ? static_cast<double>(bin) / bins : nan, hi = bin >= 0 ? (bin + 1.0) / bins : nan;
    attribute(one, "phase_lo", n == count - 1 ? 0.999 : lo);
    attribute(one, "phase_hi", n == count - 1 ? 1.0 : hi);
    attribute(one, "snapshots", n == count - 1 ? 0 : 5);
    const double t = bin >= 0 ? 0.5 * (lo + hi) * T : 0.3;
    std::vector<double> vel(nz * nx * 3, 0.0), rate(nz * nx), surface(nx);
    for (int j = 0; j < nx; ++j) {
      surface[j] = flow.surface_height(x[j], t);
      for (int k = 0; k < nz; ++k) {
        const bool empty = z[k] > surface[j];
        const double e = 1e-7;
        const double u = (flow.stream_function(x[j], z[k] + e, t) - flow.stream_function(x[j], z[k] - e, t)) / (2 * e);
        vel[(k * nx + j) * 3] = empty ? nan : u;
        rate[k * nx + j] = empty ? nan : flow.shear_rate(x[j], z[k], t);
      }
    }
    const hid_t mix = H5Gcreate2(one, "mixture", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    dataset(mix, "velocity", {static_cast<hsize_t>(nz), 1, static_cast<hsize_t>(nx), 3}, vel);
    dataset(one, "shear_rate", {static_cast<hsize_t>(nz), 1, static_cast<hsize_t>(nx)}, rate);
    dataset(one, "surface_height", {1, static_cast<hsize_t>(nx)}, surface);
    H5Gclose(mix);
    H5Gclose(one);
  }
  H5Gclose(frames);
  H5Fclose(f);
  return path;
}

}  // namespace

TEST_CASE("Phase-resolved fields interpolate in space and phase, periodic, with a moving surface",
          "[continuum][flow][phases]") {
  const SloshingFlow exact(shape());
  const grainscale::testing::TempDir tmp;  // a fresh folder, removed at the end: parallel ctest processes cannot race
  const std::string file = write_phase_file(exact, 16, tmp / "phase_fields.h5");
  REQUIRE(GriddedFlow::phase_frames(file).size() == 16u);  // the snapshot frame and the empty bin skipped
  const PhaseResolvedFlow flow = PhaseResolvedFlow::load(file, 0.4, 2.0, 0.0, true);
  CHECK(flow.phases() == 16);
  CHECK(flow.moving_surface());
  CHECK_FALSE(flow.steady());
  INFO("largest area correction " << flow.area_correction());
  CHECK(flow.area_correction() < 1e-3);

  // At a bin centre the surface is the sampled one; between centres, close to the exact wave.
  double worst_h = 0, worst_psi = 0, worst_rate = 0, max_psi = 0, max_rate = 0;
  for (double t : {0.0625, 0.3125, 0.5, 0.77, 1.3, 1.9}) {
    for (double x : {0.0, 0.05, 0.13, 0.2, 0.31, 0.4}) {
      worst_h = std::max(worst_h, std::abs(flow.surface_height(x, t) - exact.surface_height(x, t)));
      for (double sigma : {0.1, 0.4, 0.7, 1.0}) {
        const double z = sigma * exact.surface_height(x, t);
        const double zf = sigma * flow.surface_height(x, t);
        worst_psi = std::max(worst_psi, std::abs(flow.stream_function(x, zf, t) - exact.stream_function(x, z, t)));
        max_psi = std::max(max_psi, std::abs(exact.stream_function(x, z, t)));
        // γ̇ of the test flow ∝ |q| has a kink in time where q changes sign (t = 0.5, 1.5 s), which
        // no interpolation through the bins resolves: compared where the four bins the cubic uses
        // (two bin widths, 0.25 s, either side) do not straddle it.
        const bool smooth = std::abs(t - 0.5) > 0.25 && std::abs(t - 1.5) > 0.25;
        if (sigma < 1 && smooth) worst_rate = std::max(worst_rate, std::abs(flow.shear_rate(x, zf, t) - exact.shear_rate(x, z, t)));
        max_rate = std::max(max_rate, exact.shear_rate(x, z, t));
      }
    }
  }
  INFO("max |h - h_exact| = " << worst_h << " m of a = 0.015 m; max |psi - psi_exact| = " << worst_psi << " of " << max_psi
                              << "; max |rate - rate_exact| = " << worst_rate << " of " << max_rate);
  CHECK(worst_h < 0.02 * 0.015);
  CHECK(worst_psi < 0.05 * max_psi);
  CHECK(worst_rate < 0.05 * max_rate);
  // Periodic in the motion period.
  CHECK(flow.stream_function(0.13, 0.05, 0.37) == Approx(flow.stream_function(0.13, 0.05, 0.37 + 2 * 2.0)).margin(1e-15));
  CHECK(flow.surface_height(0.31, 1.7) == Approx(flow.surface_height(0.31, 1.7 - 2.0)).margin(1e-15));
  // Kinematic condition: ∂h/∂t + ∂q/∂x = 0 inside a bin; no flux through the walls and the floor.
  const double t = 0.8, dt = 1e-6, dx = 1e-6;
  for (double x : {0.05, 0.17, 0.33}) {
    const double dhdt = (flow.surface_height(x, t + dt) - flow.surface_height(x, t - dt)) / (2 * dt);
    const double dqdx = (flow.surface_flux(x + dx, t) - flow.surface_flux(x - dx, t)) / (2 * dx);
    CHECK(std::abs(dhdt + dqdx) < 1e-6 * std::abs(dhdt) + 1e-12);
    CHECK(flow.stream_function(x, flow.surface_height(x, t), t) == Approx(flow.surface_flux(x, t)).margin(1e-12));
    CHECK(flow.stream_function(x, 0.0, t) == Approx(0).margin(1e-15));
  }
  CHECK(flow.surface_flux(0.0, t) == 0);
  CHECK(std::abs(flow.surface_flux(0.4, t)) < 1e-15);
  CHECK(flow.stream_function(0.0, 0.05, t) == 0);
}

TEST_CASE("Phase-resolved fields drive the model: chaff conserved, a uniform c stays uniform", "[continuum][flow][phases]") {
  const SloshingFlow exact(shape());
  const grainscale::testing::TempDir tmp;
  const std::string file = write_phase_file(exact, 8, tmp / "phase_fields.h5");
  auto flow = std::make_shared<PhaseResolvedFlow>(PhaseResolvedFlow::load(file, 0.4, 2.0, 0.0, true));
  const int nx = 24, nz = 8;
  std::vector<double> nodes(nx + 1);
  for (int f = 0; f <= nx; ++f) nodes[f] = flow->surface_height(0.4 * f / nx, 0.0);
  Model model(Grid(0.4, nx, nz, nodes), flow);
  model.add_term(std::make_unique<Advection>(Limiter::van_leer));
  model.add_term(std::make_unique<ShearDiffusion>(0.5, 4e-3));
  model.add_term(std::make_unique<BackgroundDiffusion>(1e-6));
  IntegratorSettings s;
  s.method = "ssp_rk3";
  auto integrator = make_integrator(s, model);
  std::vector<double> uniform = model.state(0, std::vector<double>(model.size(), 0.25));
  integrator->advance(0, 3.0, uniform);
  double worst = 0;
  for (double c : model.concentration(3.0, uniform)) worst = std::max(worst, std::abs(c - 0.25));
  INFO("max |c - 0.25| = " << worst);
  CHECK(worst < 1e-12);
  model.add_term(std::make_unique<Segregation>(1e-3, Limiter::van_leer));
  auto again = make_integrator(s, model);
  std::vector<double> y = model.state(0, block(model.grid()));
  const double m0 = model.state_chaff(y);
  again->advance(0, 5.0, y);
  INFO("relative chaff change " << std::abs(model.state_chaff(y) - m0) / m0);
  CHECK(std::abs(model.state_chaff(y) - m0) < 1e-12 * m0);
}

TEST_CASE("Phase-resolved fields from YAML; bad phase input is an InputError", "[continuum][flow][phases][input]") {
  const SloshingFlow exact(shape());
  const grainscale::testing::TempDir tmp("continuum_phases");  // the field file, the YAML and its output
  const std::string file = write_phase_file(exact, 8, tmp / "phase_fields.h5");
  const std::string yaml = tmp / "run.yaml";
  auto write = [&](const std::string& flow_line, const std::string& grid_line) {
    std::ofstream(yaml) << grid_line << "\nflow: " << flow_line << R"(
terms:
  advection: {limiter: van_leer}
  segregation: {S: 1.0e-3}
  shear_diffusion: {C: 0.5, d: 4.0e-3}
initial: {type: layers, below: 0.3, above: 0.0, split: 0.5}
time: {end: 3, outputs: 3}
integrator: {method: ssp_rk3}
output: {folder: out}
)";
    return yaml;
  };
  const std::string flow_line = "{type: file, file: " + file + ", period: 2.0}";
  const ContinuumRunSummary r = run_continuum(load_continuum_settings(write(flow_line, "grid: {length: 0.4, nx: 20, nz: 6}")));
  CHECK(std::abs(r.chaff_final - r.chaff_initial) < 1e-12 * r.chaff_initial);
  // Fixed surface: the phase-mean surface, a flat bed here.
  const ContinuumSettings fixed = load_continuum_settings(
      write("{type: file, file: " + file + ", period: 2.0, surface: fixed}", "grid: {length: 0.4, nx: 20, nz: 6}"));
  CHECK(fixed.surface[3] == Approx(0.1).epsilon(1e-3));
  REQUIRE_FALSE(build_model(fixed).moving_surface());
  // Errors name the file and key: each flow line (after "{type: file, file: F, ") and what the message holds.
  const std::pair<std::string, std::vector<std::string>> bad[] = {
      {"period: 2.0, frame: 1}", {"flow.frame", "run.yaml"}},
      {"period: -2.0}", {"flow.period", "run.yaml"}},
      {"period: 2.0, surface: wavy}", {"flow.surface"}},
      // Mobility from the temperature needs one frame and a diameter in range.
      {"period: 2.0, mobility: temperature, diameter: 0.005}", {"flow.mobility", "single frame"}},
      {"frame: 0, mobility: temperature}", {"flow.diameter"}},
      {"frame: 0, mobility: temperature, diameter: 2}", {"flow.diameter"}},
      {"frame: 0, mobility: speed}", {"flow.mobility"}},
      // The volume flux is read from one frame.
      {"period: 2.0, flux: volume}", {"flow.flux", "single frame"}},
      {"frame: 0, flux: mass}", {"flow.flux"}},
  };
  for (const auto& [tail, words] : bad) {
    INFO(tail);
    try {
      load_continuum_settings(write("{type: file, file: " + file + ", " + tail, "grid: {length: 0.4, nx: 20, nz: 6}"));
      FAIL("no error");
    } catch (const grainscale::InputError& e) {
      for (const std::string& w : words) CHECK_THAT(e.what(), Contains(w));
    }
  }
  CHECK_THROWS_WITH(load_continuum_settings(write(flow_line, "grid: {length: 0.4, nx: 20, nz: 6, depth: 0.1}")),
                    Contains("grid") && Contains("run.yaml"));
}
