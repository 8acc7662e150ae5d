// Issue 9's DEM test at suite size: a real 2x DEM with an effect the base continuum model lacks, the
// container swung 0.8 m off its rotation axis, is coarse-grained and fed to `grainscale loop`, which
// must name the lever arm and cut the cross-validated error. The three stages run as the user runs
// them (the grainscale binary: dem, cg, loop), from files written here.
//
// The design is studies/loop_floating/ at half the length (docs/loop.md, "Floating chaff off the
// axis"): a 100 x 30 mm slice of 2x wheat (0.1 kg) with 15 light 12 mm balls poured on top, where they
// float, tilting +-35 deg at 0.5 Hz; 7 s, three whole cycles (about 2.5 min on 2 threads). The balls
// gather at the far end from the first cycles. The 200 mm study run for 25 s halves the CV error
// (3.54 -> 1.74); this short, small one cuts it by a third (2.57 -> 1.65, 2026-12-03): the test asserts
// a quarter, to leave room for another compiler's round-off; its on-axis twin adds nothing (docs/loop.md).
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Run `grainscale <args>` in `dir`, its output to `log` (shown on failure).
void grainscale(const fs::path& dir, const std::string& args, const std::string& log) {
  const std::string cmd = "cd '" + dir.string() + "' && '" + GRAINSCALE_BINARY + "' " + args + " > " + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  INFO("grainscale " << args << ":\n" << slurp(dir / log));
  REQUIRE(rc == 0);
}

const std::string kStudies = std::string(GRAINSCALE_SOURCE_DIR) + "/studies";

void write_case(const fs::path& dir) {
  write(dir / "off_axis.yaml", R"(name: suite_floating_off_axis
seed: 5
materials: )" + kStudies + R"(/materials/report_table1.yaml
scale_factor: 2
contact: {rolling: constant_torque, max_overlap: 0.7}
time: {end: 7.0, pour_interval: 0.005, step_fraction: 0.2}
walls:
  - {name: box, type: box_mesh, min: [0, 0, 0], max: [0.1, 0.03, 0.12], open: [+z], material: perspex,
     pivot: [-0.8, 0.015, 0.0],
     motion: {type: platform, amplitude_deg: 35, frequency: 0.5, pause: 0, axis: [0, 1, 0], start_time: 1.0}}
particles:
  - {material: barley, shape: )" + kStudies + R"(/shapes/wheat.yaml, mass: 0.1, rate: 1.0,
     region: {min: [0.005, 0.003, 0.003], max: [0.095, 0.027, 0.1]}}
  - {material: chaff, shape: )" + kStudies + R"(/shapes/chaff_float.yaml, mass: 0.00135, rate: 0.0135, start: 0.4,
     region: {min: [0.005, 0.003, 0.065], max: [0.095, 0.027, 0.115]}}
output: {directory: dem, snapshot_interval: 0.1, progress_interval: 60, checkpoint_interval: 300}
)");
  const std::string cg_common = R"(snapshot_dir: dem/snapshots
container: {wall: box, lo: [0, 0, 0], hi: [0.1, 0.03, 0.12]}
grid: {dimension: 2, cells: [10, 1, 12]}
kernel: {type: gaussian, width: 1.0, diameter: 0.0067}
species:
  chaff: {chaff: true, density: 100}
  barley: {density: 1380}
surface: {fraction: 0.2}
measures: {slice_width: 0.025, end_length: 0.025}
)";
  write(dir / "cg.yaml", cg_common + "averaging: {mode: cycles, period: 2.0, t0: 1.0, to: 7.0}\noutput: cg\n");
  write(dir / "cg_flow.yaml", cg_common + "averaging: {mode: window, from: 1.0, to: 7.0}\noutput: cg_flow\n");
  write(dir / "model.yaml", R"(flow: {type: file, file: cg_flow/fields.h5, flux: volume}
grid: {length: 0.1, nx: 10, nz: 6}
terms:
  advection: {limiter: van_leer}
  segregation: {S: 1.0e-3, limiter: van_leer}
  shear_diffusion: {C: 0.5, d: 6.7e-3}
  background_diffusion: {D0: 1.0e-6}
initial: {type: file, file: cg/fields.h5, frame: 0, min_solid_fraction: 0.1}
time: {end: 8, outputs: 4}
integrator: {method: cvode, rtol: 1.0e-6, atol: 1.0e-10}
output: {folder: continuum, slice_width: 0.025}
)");
  write(dir / "fit.yaml", R"(model: model.yaml
data: {fields: cg/fields.csv, field_sigma: 0.078, t0: 1.95, from: 2.5, min_solid_fraction: 0.1}
fit: {parameters: [S, C, D0], max_iterations: 30}
output: fit
)");
  write(dir / "loop.yaml", R"(fit: fit.yaml
scenario: off_axis.yaml
container: box
candidates: {lever_arm: {}, surface_drift: {}, concentration_segregation: {}, clustering_diffusion: {},
             wall_mobility: {}, pause_creep: {}}
cv: {by: time, blocks: 2}
candidate_iterations: 60
output: loop
)");
}

}  // namespace

TEST_CASE("grainscale loop names the lever arm in a small 2x DEM swung off its axis and cuts the held-out error",
          "[studies][loop][lever_arm][dem]") {
  const fs::path dir = fs::temp_directory_path() / ("grainscale_test_loop_dem_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_case(dir);

  grainscale(dir, "dem off_axis.yaml --threads 2", "dem.log");
  grainscale(dir, "cg cg.yaml", "cg.log");
  grainscale(dir, "cg cg_flow.yaml", "cg_flow.log");
  grainscale(dir, "loop loop.yaml", "loop.log");

  const YAML::Node out = YAML::LoadFile((dir / "loop/loop.yaml").string());
  INFO(slurp(dir / "loop/report.md"));
  // The motion the loop read from the scenario: the axis 0.8 m from the box, <omega^2> of a
  // +-35 deg, 0.5 Hz cosine (Omega^2 A^2 / 2 = 1.84 1/s^2).
  CHECK(out["motion"]["axis_x"].as<double>() == Approx(-0.8));
  CHECK(out["motion"]["omega2_mean"].as<double>() == Approx(1.84).margin(0.01));
  // Three whole cycles: the first is the model's start, the other two its data.
  CHECK(out["data"]["times"].as<int>() == 2);

  REQUIRE(out["chosen"].as<std::string>() == "lever_arm");
  const double base_cv = out["base"]["cv"]["error"].as<double>();
  const YAML::Node ranked = out["candidates"];
  REQUIRE(ranked[0]["name"].as<std::string>() == "lever_arm");
  const double lever_cv = ranked[0]["cv"]["error"].as<double>();
  // The base misses the far-end pile by several sigma; the lever arm explains a third of it here
  // (measured 2.57 -> 1.65), and it is first by a margin (surface_drift, next, 1.98).
  CHECK(base_cv > 2.0);
  CHECK(lever_cv < 0.75 * base_cv);
  CHECK(lever_cv < 0.9 * ranked[1]["cv"]["error"].as<double>());
  fs::remove_all(dir);
}
