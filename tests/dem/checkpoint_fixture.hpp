#pragma once
// A small scenario that exercises everything a checkpoint must carry: wheat clumps and loose spheres
// (two rolling-model histories per contact with EPSD), a triangle-mesh box that surges back and forth
// (moving wall, wall-contact histories on mesh features), a plane wall, and a pour still running
// half-way. Written into a temporary folder; removed with it.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "dem/simulation.hpp"

namespace grainscale::dem::testing {

namespace fs = std::filesystem;

/// A fresh directory under the system temp directory, removed with everything in it at scope exit.
struct CheckpointTempDir {
  fs::path path;
  CheckpointTempDir() {
    std::string tmpl = (fs::temp_directory_path() / "grainscale_checkpoint_XXXXXX").string();
    REQUIRE(mkdtemp(tmpl.data()) != nullptr);
    path = tmpl;
  }
  ~CheckpointTempDir() {
    std::error_code ec;
    fs::permissions(path, fs::perms::owner_all, fs::perm_options::add, ec);
    for (auto& e : fs::recursive_directory_iterator(path, ec)) {
      if (e.is_directory(ec)) fs::permissions(e.path(), fs::perms::owner_all, fs::perm_options::add, ec);
    }
    fs::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

inline std::string slurp_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline const char* kCheckpointMaterials = R"(materials:
  grain: {density: 1000, shear_modulus: 5.0e5, poisson_ratio: 0.3}
  wall:  {density: 1190, shear_modulus: 7.97e8, poisson_ratio: 0.38}
pairs:
  grain-grain: {restitution: 0.2, friction: 0.5, rolling_friction: 0.1}
  grain-wall:  {restitution: 0.2, friction: 0.4, rolling_friction: 0.05}
)";

/// The scenario text; `extra_output` goes into the output map (e.g. "checkpoint_interval: 1.0e-9"),
/// `extra_time` into the time map (e.g. "step_control: stability").
inline std::string checkpoint_scenario(double end_time, const std::string& extra_output = "",
                                       const std::string& extra_time = "") {
  return std::string(R"(name: checkpoint_test
seed: 11
gravity: [0, 0, -150]
materials: materials.yaml
contact: {rolling: epsd}
time: {end: )") + std::to_string(end_time) + ", pour_interval: 0.002" +
         (extra_time.empty() ? "" : ", " + extra_time) + R"(}
walls:
  - {name: box, type: box_mesh, min: [0, 0, 0], max: [0.04, 0.03, 0.06], open: [+z], material: wall,
     motion: {type: sinusoids, surge: {amplitude: 0.002, period: 0.04}}}
  - {name: shelf, type: plane, point: [0, 0, 0.002], normal: [0.2, 0, 1], material: wall}
particles:
  - {material: grain, shape: )" GRAINSCALE_SOURCE_DIR R"(/studies/shapes/wheat.yaml, count: 14,
     velocity: [0.1, 0, -0.6], region: {min: [0.001, 0.001, 0.0], max: [0.039, 0.029, 0.016]}}
  - {material: grain, diameter: 0.003, diameter_spread: 0.1, count: 60, velocity: [0, 0, -0.6],
     region: {min: [0.001, 0.001, 0.016], max: [0.039, 0.029, 0.045]}}
  - {material: grain, diameter: 0.0032, mass: 0.0006, rate: 0.012, start: 0.002,
     region: {min: [0.003, 0.001, 0.045], max: [0.037, 0.029, 0.059]}}
output: {directory: out, snapshot_interval: 0.01)" +
         (extra_output.empty() ? "" : ", " + extra_output) + "}\n";
}

/// The scenario (as `name`) and its materials in `dir`; returns the scenario's path.
inline std::string write_checkpoint_scenario(const CheckpointTempDir& dir, double end_time,
                                             const std::string& extra_output = "",
                                             const std::string& name = "scenario.yaml",
                                             const std::string& extra_time = "") {
  std::ofstream(dir / "materials.yaml") << kCheckpointMaterials;
  std::ofstream(dir / name) << checkpoint_scenario(end_time, extra_output, extra_time);
  return dir / name;
}

/// Every body's and sphere's state, bit for bit, in storage order (slot order for spheres).
inline void require_identical(const Simulation& a, const Simulation& b) {
  REQUIRE(a.steps() == b.steps());
  const double ta = a.time(), tb = b.time();
  REQUIRE(std::memcmp(&ta, &tb, sizeof(double)) == 0);
  const Bodies &ba = a.bodies(), &bb = b.bodies();
  REQUIRE(ba.size() == bb.size());
  const std::size_t nb = ba.size();
  CHECK(std::memcmp(ba.x.data(), bb.x.data(), nb * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(ba.v.data(), bb.v.data(), nb * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(ba.L.data(), bb.L.data(), nb * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(ba.omega.data(), bb.omega.data(), nb * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(ba.q.data(), bb.q.data(), nb * sizeof(Quat)) == 0);
  CHECK(std::memcmp(ba.force.data(), bb.force.data(), nb * sizeof(Vec3)) == 0);
  const Particles &pa = a.particles(), &pb = b.particles();
  REQUIRE(pa.size() == pb.size());
  CHECK(pa.id == pb.id);  // same slot order
  CHECK(std::memcmp(pa.x.data(), pb.x.data(), pa.size() * sizeof(Vec3)) == 0);
  CHECK(std::memcmp(pa.v.data(), pb.v.data(), pa.size() * sizeof(Vec3)) == 0);
  CHECK(a.neighbors().builds() == b.neighbors().builds());
}

}  // namespace grainscale::dem::testing
