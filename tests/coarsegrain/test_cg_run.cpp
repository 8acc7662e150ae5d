// The coarse-graining run: settings checked key by key (every mistake an InputError naming the key),
// and an end-to-end run on snapshots written by the DEM stage from a tilted container, whose outputs
// follow docs/coarsegrain_layout.md.
#include <hdf5.h>
#include <stdlib.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

#include "coarsegrain/cg_run.hpp"
#include "coarsegrain/field_file.hpp"
#include "dem/input_error.hpp"
#include "dem/snapshot.hpp"
#include "dem/motion/platform_tilt.hpp"
#include "dem/walls/plane.hpp"

using namespace grainscale;
using namespace grainscale::cg;
using Catch::Matchers::WithinAbs;

namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "grainscale_cg_XXXXXX").string();
    REQUIRE(mkdtemp(tmpl.data()) != nullptr);
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

std::string slurp(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const std::string& file, const std::string& text) { std::ofstream(file) << text; }

const char* kGoodSettings = R"(snapshots:
  - {path: snap_a.h5}
  - {path: snap_b.h5, phase: 0.5}
container: {wall: floor, lo: [0, 0, 0], hi: [0.4, 0.1, 0.05]}
grid: {dimension: 2, cells: [40, 1, 10]}
kernel: {type: lucy, width: 1.0, diameter: 0.004, boundary: reflect}
species:
  chaff: {chaff: true}
  wheat: {density: 1380}
averaging: {mode: window}
measures: {slice_width: 0.05, end_length: 0.1, pixel: 0.001, layer_thickness: 0}
output: out
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

/// Wheat and chaff spheres (radius 2 mm) in one layer on the floor of a container tilted by 0.3 rad
/// about its width and displaced: chaff in the left quarter, wheat elsewhere. Written as a
/// layout-2 snapshot by the DEM stage itself.
void write_tilted_container_snapshot(const std::string& path) {
  dem::MaterialTable materials;
  materials.add({"wheat", 1380, 2.6e6, 0.3});
  materials.add({"chaff", 100, 1.0e6, 0.4});
  materials.add({"perspex", 1190, 7.97e8, 0.38});
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) materials.set_pair(a, b, {0.5, 0.3, 0.01, true});
  dem::Simulation sim(materials, {});
  dem::WallPose pose;
  pose.origin = {1.0, 2.0, 0.5};
  pose.orientation = dem::axis_angle({0, 1, 0}, 0.3);
  pose.angular_velocity = {0, 0.1, 0};
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 40; ++i) {
      const dem::Vec3 xc{0.005 + 0.01 * i, 0.005 + 0.01 * j, 0.0021};
      // At rest in the container: world velocity = the frame's rigid motion at that point.
      const dem::Vec3 xw = pose.origin + dem::rotate(pose.orientation, xc);
      sim.add_sphere(xc.x < 0.1 ? 1 : 0, 0.002, xw, pose.surface_velocity(xw));
    }
  sim.add_wall("floor", std::make_shared<dem::PlaneGeometry>(dem::Vec3{0, 0, 0}, dem::Vec3{0, 0, 1}), 2, pose);
  dem::write_snapshot(sim, path, {"cg test", 1});
}

}  // namespace

TEST_CASE("Coarse-graining settings: every mistake is an InputError naming the key", "[cg][settings]") {
  TempDir dir;
  write_text(dir / "good.yaml", kGoodSettings);
  const CgSettings good = load_cg_settings(dir / "good.yaml");
  CHECK(good.snapshots.size() == 2);
  CHECK(good.snapshots[0].path == dir / "snap_a.h5");  // relative to the settings file
  CHECK(std::isnan(good.snapshots[0].phase));
  CHECK(good.snapshots[1].phase == 0.5);
  CHECK(good.kernel == KernelType::lucy);
  CHECK(good.chaff == std::vector<std::string>{"chaff"});
  CHECK(good.density.at("wheat") == 1380);
  CHECK(good.averaging == Averaging::window);
  CHECK(good.output_dir == dir / "out");

  struct Bad {
    std::string from, to, says;
  };
  const Bad bad = GENERATE(Bad{"grid: {dimension: 2", "grid: {dimension: 4", "grid.dimension"},
                           Bad{"width: 1.0", "width: 0", "kernel.width"},
                           Bad{"boundary: reflect", "boundary: reflect, bondary: 1", "kernel.bondary"},
                           Bad{"type: lucy", "type: cubic", "kernel.type"},
                           Bad{"hi: [0.4, 0.1, 0.05]", "hi: [0.4, 0.0, 0.05]", "container.hi"},
                           Bad{"chaff: {chaff: true}", "chaff: {chaff: yes please}", "species.chaff.chaff"},
                           Bad{"chaff: {chaff: true}", "chaff: {}", "chaff: true"},
                           Bad{"wheat: {density: 1380}", "wheat: {density: -5}", "species.wheat.density"},
                           // (phase averaging without a period: see the recorded-phase test below)
                           Bad{"averaging: {mode: window}", "averaging: {mode: cycles}", "averaging.period"},
                           Bad{"averaging: {mode: window}", "averaging: {mode: cycle, period: 2}", "averaging.mode"},
                           Bad{"end_length: 0.1", "end_length: 0.3", "measures.end_length"},
                           Bad{"cells: [40, 1, 10]", "cells: [40, 1]", "grid.cells"},
                           Bad{"output: out\n", "", "output"},
                           Bad{"  - {path: snap_a.h5}", "  - {path: snap_a.h5, phaze: 1}", "snapshots[0].phaze"},
                           Bad{"snapshots:", "snapshot_dir: .\nsnapshots:", "exactly one"});
  CAPTURE(bad.to);
  write_text(dir / "bad.yaml", replace(kGoodSettings, bad.from, bad.to));
  REQUIRE_THROWS_AS(load_cg_settings(dir / "bad.yaml"), InputError);
  REQUIRE_THROWS_WITH(load_cg_settings(dir / "bad.yaml"), Catch::Contains(bad.says));
}

TEST_CASE("A coarse-graining run writes fields (HDF5 + XDMF) and the report's profiles (CSV)", "[cg][run]") {
  TempDir dir;
  write_tilted_container_snapshot(dir / "snap_a.h5");
  write_tilted_container_snapshot(dir / "snap_b.h5");
  write_text(dir / "cg.yaml", kGoodSettings);
  const CgSettings settings = load_cg_settings(dir / "cg.yaml");
  const CgSummary summary = run_coarse_graining(settings);

  CHECK(summary.snapshots == 2);
  CHECK(summary.frames == 1);  // window average
  CHECK(summary.max_mass_error < 1e-12);
  CHECK(summary.kernel_width == 0.004);
  // Chaff in the left 100 mm only, wheat elsewhere, one layer: the left end zone is all chaff.
  const CongregationIndex& ci = summary.congregation.front();
  CHECK(ci.share_left == 4.0);   // all chaff in the zone, which is a quarter of the length
  CHECK(ci.share_right == 0.0);
  CHECK(ci.coverage_left == 1.0);
  CHECK(ci.coverage_right == 0.0);

  const std::string slices = slurp(dir / "out/slices.csv");
  INFO(slices.substr(0, 400));
  CHECK(slices.rfind("t_s,x_m,chaff_percent,", 0) == 0);
  CHECK(slices.find("\n0,0.025000000000000001,50,0,0.050000000000000003,50,0,1,1\n") != std::string::npos);
  CHECK(slurp(dir / "out/coverage.csv").rfind("t_s,x_m,coverage,", 0) == 0);
  CHECK(slurp(dir / "out/fields.csv").rfind("t_s,x_m,z_m,c,", 0) == 0);
  CHECK(slurp(dir / "out/summary.yaml").find("max_mass_error") != std::string::npos);
  const std::string xmf = slurp(dir / "out/fields.xmf");
  CHECK(xmf.find("3DCoRectMesh") != std::string::npos);
  CHECK(xmf.find("fields.h5:/frames/000000/mixture/density") != std::string::npos);
  CHECK(!fs::exists(dir / "out/fields.h5.tmp"));

  // The field file: layout version, grid, and the fields in the container frame: the layer's
  // particles rest in the container (zero relative velocity although the container turns).
  const hid_t f = H5Fopen((dir / "out/fields.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  int version = 0;
  const hid_t a = H5Aopen(f, "cg_layout_version", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_INT, &version);
  H5Aclose(a);
  CHECK(version == kFieldLayoutVersion);
  const hid_t d = H5Dopen2(f, "/frames/000000/mixture/velocity", H5P_DEFAULT);
  REQUIRE(d >= 0);
  const hid_t space = H5Dget_space(d);
  hsize_t dims[4] = {0, 0, 0, 0};
  REQUIRE(H5Sget_simple_extent_ndims(space) == 4);
  H5Sget_simple_extent_dims(space, dims, nullptr);
  CHECK(dims[0] == 10);
  CHECK(dims[1] == 1);
  CHECK(dims[2] == 40);
  CHECK(dims[3] == 3);
  std::vector<double> u(dims[0] * dims[1] * dims[2] * dims[3]);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u.data());
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  // Cell (x index 5, z index 0): holds the layer.
  for (int c = 0; c < 3; ++c) CHECK_THAT(u[3 * 5 + static_cast<std::size_t>(c)], WithinAbs(0, 1e-15));
}

TEST_CASE("A coarse-graining run names a missing snapshot or an unknown container wall", "[cg][run]") {
  TempDir dir;
  write_text(dir / "cg.yaml", kGoodSettings);
  REQUIRE_THROWS_AS(run_coarse_graining(load_cg_settings(dir / "cg.yaml")), InputError);  // no snap_a.h5
  write_tilted_container_snapshot(dir / "snap_a.h5");
  write_tilted_container_snapshot(dir / "snap_b.h5");
  write_text(dir / "cg.yaml", replace(kGoodSettings, "wall: floor", "wall: lid"));
  REQUIRE_THROWS_WITH(run_coarse_graining(load_cg_settings(dir / "cg.yaml")), Catch::Contains("'lid'") && Catch::Contains("floor"));
}

TEST_CASE("Phase averaging takes each snapshot's phase from the container's recorded motion", "[cg][run]") {
  // A floor on the report's platform profile (18 s cycle, starting at the +A hold: phase = t / 18),
  // snapshots at phases 0.11, 0.36, 0.61 and 0.86; no 'period' given: each lands in its own bin.
  const TempDir dir;
  dem::MaterialTable materials;
  materials.add({"wheat", 1380, 2.6e6, 0.3});
  materials.add({"chaff", 100, 1.0e6, 0.4});
  materials.add({"perspex", 1190, 7.97e8, 0.38});
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) materials.set_pair(a, b, {0.5, 0.3, 0.01, true});
  dem::SimulationSettings st;
  st.gravity = {0, 0, 0};
  st.time_step = 0.01;
  dem::Simulation sim(materials, st);
  for (int i = 0; i < 8; ++i) sim.add_sphere(i % 2, 0.002, {0.05 + 0.04 * i, 0.05, 0.02});
  sim.add_wall("floor", std::make_shared<dem::PlaneGeometry>(dem::Vec3{0, 0, 0}, dem::Vec3{0, 0, 1}), 2);
  dem::PlatformTilt::Params tilt;
  tilt.amplitude = 0.1;
  tilt.start_level = false;
  sim.walls().back().set_motion({std::make_shared<dem::PlatformTilt>(tilt), {0, 0, 0}});
  sim.setup();
  std::string list;
  for (double t : {2.0, 6.5, 11.0, 15.5}) {
    while (sim.time() < t - 1e-9) sim.step();
    const std::string name = "snap_" + std::to_string(static_cast<int>(t * 10)) + ".h5";
    dem::write_snapshot(sim, dir / name, {"phase test", 1});
    list += "  - {path: " + name + "}\n";
  }
  const std::string settings = dir / "cg.yaml";
  write_text(settings, "snapshots:\n" + list +
                           "container: {wall: floor, lo: [0, 0, -0.05], hi: [0.4, 0.1, 0.05]}\n"
                           "grid: {dimension: 1, cells: [8, 1, 1]}\n"
                           "kernel: {width: 1.0, diameter: 0.004}\n"
                           "species: {chaff: {chaff: true}}\n"
                           "averaging: {mode: phase, phase_bins: 4}\n"
                           "output: out\n");
  const CgSummary summary = run_coarse_graining(load_cg_settings(settings));
  CHECK(summary.frames == 4);  // one per phase bin: the recorded phases were used

  // Without a moving container (and without period or phases) it is a clear error.
  write_text(settings, "snapshots:\n" + list +
                           "container: {lo: [0, 0, -0.05], hi: [0.4, 0.1, 0.05]}\n"
                           "grid: {dimension: 1, cells: [8, 1, 1]}\n"
                           "kernel: {width: 1.0, diameter: 0.004}\n"
                           "averaging: {mode: phase, phase_bins: 4}\n"
                           "output: out\n");
  CHECK_THROWS_AS(load_cg_settings(settings), InputError);
}

TEST_CASE("Averaging by cycles gives one frame per whole motion cycle, the window average of its snapshots", "[cg][run]") {
  // One chaff sphere drifting at 0.1 m/s along x (no gravity, no contacts), snapshots every 0.25 s
  // from 0 to 2.25 s; cycles of 1 s from t0 = 0: [0, 1) and [1, 2) are whole (4 snapshots each),
  // [2, 3) holds only 2 and is left out.
  const TempDir dir;
  dem::MaterialTable materials;
  materials.add({"chaff", 100, 1.0e6, 0.4});
  materials.set_pair(0, 0, {0.5, 0.3, 0.01, true});
  dem::SimulationSettings st;
  st.gravity = {0, 0, 0};
  st.time_step = 0.0005;
  dem::Simulation sim(materials, st);
  sim.add_sphere(0, 0.002, {0.02, 0.05, 0.02}, {0.1, 0, 0});
  sim.setup();
  std::string all, first_cycle;
  for (int k = 0; k < 10; ++k) {
    // Snapshots a little early, as a DEM's at the step nearest their time (1 s at 0.9995 s).
    while (sim.time() < 0.25 * k - 0.0005 - 1e-9) sim.step();
    const std::string name = "snap_" + std::to_string(k) + ".h5";
    dem::write_snapshot(sim, dir / name, {"cycles test", 1});
    all += "  - {path: " + name + "}\n";
    if (k < 4) first_cycle += "  - {path: " + name + "}\n";
  }
  const std::string common = "container: {lo: [0, 0, 0], hi: [0.4, 0.1, 0.04]}\n"
                             "grid: {dimension: 1, cells: [40, 1, 1]}\n"
                             "kernel: {width: 1.0, diameter: 0.004}\n"
                             "species: {chaff: {chaff: true}}\n";
  write_text(dir / "cycles.yaml", "snapshots:\n" + all + common + "averaging: {mode: cycles, period: 1.0, t0: 0}\noutput: cycles\n");
  write_text(dir / "window.yaml", "snapshots:\n" + first_cycle + common + "averaging: {mode: window}\noutput: window\n");
  const CgSummary cycles = run_coarse_graining(load_cg_settings(dir / "cycles.yaml"));
  CHECK(cycles.frames == 2);
  run_coarse_graining(load_cg_settings(dir / "window.yaml"));

  // The first cycle's frame is the window average of snapshots 0-3: the same rows, bit for bit,
  // at their mean time (0.375 s less the snapshots' lead); the second frame is a second later.
  const std::string c = slurp(dir / "cycles/fields.csv"), w = slurp(dir / "window/fields.csv");
  REQUIRE(c.size() > w.size());
  CHECK(c.substr(0, w.size()) == w);
  const std::size_t row = w.find('\n') + 1, second = w.size();
  CHECK_THAT(std::stod(w.substr(row)), WithinAbs(0.375 - 0.0005 * 3 / 4, 1e-9));  // the first at 0 s exactly
  CHECK_THAT(std::stod(c.substr(second)), WithinAbs(1.375 - 0.0005, 1e-9));

  // averaging.from/to pick a time range: the window over [0.9, 1.6] s holds the snapshots at 1,
  // 1.25 and 1.5 s (mean time 1.25 s).
  write_text(dir / "range.yaml", "snapshots:\n" + all + common + "averaging: {mode: window, from: 0.9, to: 1.6}\noutput: range\n");
  const CgSummary range = run_coarse_graining(load_cg_settings(dir / "range.yaml"));
  CHECK(range.snapshots == 3);
  const std::string r = slurp(dir / "range/fields.csv");
  CHECK_THAT(std::stod(r.substr(r.find('\n') + 1)), WithinAbs(1.25 - 0.0005, 1e-9));
  write_text(dir / "none.yaml", "snapshots:\n" + all + common + "averaging: {mode: window, from: 5}\noutput: none\n");
  REQUIRE_THROWS_WITH(run_coarse_graining(load_cg_settings(dir / "none.yaml")), Catch::Contains("no snapshot lies in"));
  write_text(dir / "back.yaml", "snapshots:\n" + all + common + "averaging: {mode: window, from: 2, to: 1}\noutput: back\n");
  REQUIRE_THROWS_WITH(load_cg_settings(dir / "back.yaml"), Catch::Contains("averaging.to"));

  // Without a whole cycle (t0 after the last full one) it is a clear error naming the period.
  write_text(dir / "late.yaml", "snapshots:\n" + all + common + "averaging: {mode: cycles, period: 1.0, t0: 2.0}\noutput: late\n");
  REQUIRE_THROWS_WITH(run_coarse_graining(load_cg_settings(dir / "late.yaml")), Catch::Contains("no whole cycle"));
}
