// HDF5 snapshots: exact round trip in id order whatever the slot order, metadata, atomic replacement,
// input errors that name the file and the object, and the XDMF time series for ParaView.
#include "dem/shape.hpp"
#include "dem/snapshot.hpp"

#include <hdf5.h>
#include <stdlib.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <numeric>
#include <regex>
#include <string>
#include <vector>

#include "dem/input_error.hpp"
#include "dem/container_meshes.hpp"
#include "dem/motion/platform_tilt.hpp"
#include "dem/walls/mesh.hpp"
#include "dem/walls/plane.hpp"
#include "grainscale_version.hpp"

namespace grainscale::dem {
namespace {

namespace fs = std::filesystem;

/// A fresh directory under the system temp directory, removed with everything in it at scope exit.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "grainscale_snapshot_XXXXXX").string();
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

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}
bool same_bits(const Quat& a, const Quat& b) {
  return same_bits(a.w, b.w) && same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

MaterialTable grain_materials() {
  MaterialTable t;
  t.add({"barley", 1380, 2.6e6, 0.3});
  t.add({"chaff", 300, 1.0e6, 0.3});
  t.add({"steel", 7800, std::numeric_limits<double>::infinity(), 0.3});
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) t.set_pair(a, b, {0.5, 0.3, 0.05, true});
  return t;
}

/// 48 spheres of two materials in a loose 4x4x3 lattice above a floor, added in a scrambled order
/// (so the cell sort renumbers them at once) with scattered velocities and spins, run long enough for
/// several neighbour-list rebuilds. A second, tilted and moving wall is out of reach and only there to
/// have a non-trivial pose to record. Built once and shared (read-only) to keep the tests fast.
const Simulation& busy_simulation() {
  static const std::unique_ptr<Simulation> sim = [] {
    SimulationSettings settings;
    settings.scale_factor = 2.5;
    auto s = std::make_unique<Simulation>(grain_materials(), settings);
    const int n = 48;
    for (int k = 0; k < n; ++k) {
      const int c = (k * 29) % n;  // 29 is coprime to 48: a permutation of the lattice sites
      const Vec3 x{0.003 * (c % 4), 0.003 * ((c / 4) % 4), 0.002 + 0.003 * (c / 16)};
      const Vec3 v{0.4 * std::sin(1.3 * k), 0.4 * std::cos(0.7 * k), -0.2 * std::sin(0.3 * k)};
      const Vec3 w{50.0 * std::cos(2.1 * k), 30.0 * std::sin(k), 10.0};
      s->add_sphere(k % 3 == 0 ? 1 : 0, 0.001 * (1 + 0.1 * (k % 4)), x, v, w);
    }
    s->add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 2);
    WallPose tilted;
    tilted.origin = {0.5, -0.25, 0.125};
    tilted.orientation = axis_angle({0, 1, 0}, 0.3);
    tilted.velocity = {0.01, 0, -0.02};
    tilted.angular_velocity = {0, 0.5, 0};
    s->add_wall("side", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{-1, 0, 0}), 2, tilted);
    s->run_steps(200);
    return s;
  }();
  return *sim;
}

bool slots_in_id_order(const Particles& p) {
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.id[i] != i) return false;
  return true;
}

const SnapshotInfo kInfo{"snapshot test <&\"'> séance", 0xFEDCBA9876543210ull};

void check_matches(const Snapshot& s, const Simulation& sim) {
  CHECK(s.layout_version == kSnapshotLayoutVersion);
  CHECK(same_bits(s.time, sim.time()));
  CHECK(s.step == sim.steps());
  CHECK(same_bits(s.scale_factor, sim.settings().scale_factor));
  CHECK(s.units == "SI: m, kg, s, rad");
  CHECK(s.code_version == std::string(grainscale::version) + " " + grainscale::git_revision);
  CHECK(s.scenario_name == kInfo.scenario_name);
  CHECK(s.seed == kInfo.seed);
  REQUIRE(s.material_names.size() == static_cast<std::size_t>(sim.materials().size()));
  for (int m = 0; m < sim.materials().size(); ++m) CHECK(s.material_names[m] == sim.materials()[m].name);

  const Particles& p = sim.particles();
  REQUIRE(s.id.size() == p.size());
  REQUIRE(s.material.size() == p.size());
  REQUIRE(s.radius.size() == p.size());
  REQUIRE(s.mass.size() == p.size());
  REQUIRE(s.position.size() == p.size());
  REQUIRE(s.velocity.size() == p.size());
  REQUIRE(s.angular_velocity.size() == p.size());
  REQUIRE(s.orientation.size() == p.size());
  CHECK(std::is_sorted(s.id.begin(), s.id.end()));
  for (std::size_t k = 0; k < s.id.size(); ++k) {
    const std::size_t i = p.slot_of(s.id[k]);
    REQUIRE(i < p.size());
    CHECK(s.material[k] == p.material[i]);
    CHECK(same_bits(s.radius[k], p.radius[i]));
    CHECK(same_bits(s.mass[k], p.mass_share[i]));
    CHECK(same_bits(s.position[k], p.x[i]));
    CHECK(same_bits(s.velocity[k], p.v[i]));
    CHECK(same_bits(s.angular_velocity[k], p.omega[i]));
    CHECK(same_bits(s.orientation[k], p.q[i]));
  }

  REQUIRE(s.walls.size() == sim.walls().size());
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const WallPose& pose = sim.walls()[w].pose();
    CHECK(s.walls[w].name == sim.walls()[w].name());
    CHECK(same_bits(s.walls[w].origin, pose.origin));
    CHECK(same_bits(s.walls[w].orientation, pose.orientation));
    CHECK(same_bits(s.walls[w].velocity, pose.velocity));
    CHECK(same_bits(s.walls[w].angular_velocity, pose.angular_velocity));
  }
}

/// Edit a written snapshot with the raw C API to make the broken files a reader must reject.
struct RawFile {
  hid_t id;
  explicit RawFile(const std::string& path) : id(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT)) { REQUIRE(id >= 0); }
  ~RawFile() { H5Fclose(id); }
  void remove(const char* link) const { REQUIRE(H5Ldelete(id, link, H5P_DEFAULT) >= 0); }
  void set_int_attribute(const char* name, int value) const {
    const hid_t a = H5Aopen(id, name, H5P_DEFAULT);
    REQUIRE(a >= 0);
    CHECK(H5Awrite(a, H5T_NATIVE_INT, &value) >= 0);
    H5Aclose(a);
  }
  void replace_ids(const std::vector<std::uint64_t>& ids) const {
    remove("/particles/id");
    const hsize_t rows = ids.size();
    const hid_t space = H5Screate_simple(1, &rows, nullptr);
    const hid_t d = H5Dcreate2(id, "/particles/id", H5T_STD_U64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    CHECK(H5Dwrite(d, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ids.data()) >= 0);
    H5Dclose(d);
    H5Sclose(space);
  }
  void add_dataset(const char* name, hsize_t rows) const {
    const hid_t space = H5Screate_simple(1, &rows, nullptr);
    const hid_t d = H5Dcreate2(id, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const std::vector<double> zeros(rows, 0.0);
    CHECK(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data()) >= 0);
    H5Dclose(d);
    H5Sclose(space);
  }
};

/// Open HDF5 files, groups, datasets, attributes and named types, in every file. Zero after a
/// failing call means its error path closed everything it opened (dataspaces and property lists are
/// not counted; HDF5 1.10 offers no public count for them).
ssize_t open_hdf5_objects() { return H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL); }

/// The InputError message of read_snapshot(path), or "" if it did not throw one.
std::string read_error(const std::string& path) {
  try {
    read_snapshot(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string write_error(const Simulation& sim, const std::string& path) {
  try {
    write_snapshot(sim, path, kInfo);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

using Catch::Matchers::Contains;

}  // namespace

TEST_CASE("snapshot round-trips every field bit for bit, in id order", "[dem][snapshot]") {
  const TempDir dir;
  const Simulation& sim = busy_simulation();
  REQUIRE(sim.neighbors().builds() > 2);            // particles moved between cells...
  REQUIRE_FALSE(slots_in_id_order(sim.particles()));  // ...and slots are not in id order

  const std::string file = dir / "state.h5";
  write_snapshot(sim, file, kInfo);
  CHECK_FALSE(fs::exists(file + ".tmp"));
  CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()) == 1);

  const Snapshot s = read_snapshot(file);
  check_matches(s, sim);
  for (std::size_t k = 0; k < s.id.size(); ++k) CHECK(s.id[k] == k);
}

TEST_CASE("snapshot files are byte-identical for the same state in any slot order", "[dem][snapshot]") {
  const TempDir dir;
  const Simulation& sim = busy_simulation();
  write_snapshot(sim, dir / "a.h5", kInfo);
  write_snapshot(sim, dir / "b.h5", kInfo);
  CHECK(slurp(dir / "a.h5") == slurp(dir / "b.h5"));

  // Renumber the slots (as a neighbour-list rebuild would): same physical state, same file.
  Simulation renumbered = sim;
  std::vector<std::uint32_t> reversed(renumbered.particles().size());
  std::iota(reversed.rbegin(), reversed.rend(), 0u);
  renumbered.particles().permute(reversed);
  REQUIRE(renumbered.particles().id != sim.particles().id);
  write_snapshot(renumbered, dir / "c.h5", kInfo);
  CHECK(slurp(dir / "a.h5") == slurp(dir / "c.h5"));
}

TEST_CASE("snapshot with no particles, no walls or no materials", "[dem][snapshot]") {
  const TempDir dir;
  SimulationSettings settings;
  settings.time_step = 1e-6;
  {
    Simulation empty(grain_materials(), settings);
    empty.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 2);
    write_snapshot(empty, dir / "no_particles.h5", kInfo);
    const Snapshot s = read_snapshot(dir / "no_particles.h5");
    check_matches(s, empty);
    CHECK(s.id.empty());
    CHECK(s.position.empty());
    CHECK(s.walls.size() == 1);
  }
  {
    Simulation bare(MaterialTable{}, settings);
    write_snapshot(bare, dir / "nothing.h5", {});
    const Snapshot s = read_snapshot(dir / "nothing.h5");
    CHECK(s.material_names.empty());
    CHECK(s.id.empty());
    CHECK(s.walls.empty());
    CHECK(s.scenario_name.empty());
  }
  {
    Simulation one(grain_materials(), settings);
    one.add_sphere(0, 0.001, {0, 0, 0.01});
    write_snapshot(one, dir / "no_walls.h5", kInfo);
    check_matches(read_snapshot(dir / "no_walls.h5"), one);
  }
}

TEST_CASE("a failed snapshot write leaves the previous file intact and no tmp file", "[dem][snapshot]") {
  const TempDir dir;
  const Simulation& sim = busy_simulation();
  const std::string good = dir / "good.h5";
  write_snapshot(sim, good, kInfo);
  const std::string before = slurp(good);

  SECTION("directory does not exist") {
    const std::string missing = dir / "no/such/dir/state.h5";
    CHECK_THAT(write_error(sim, missing), Contains(missing) && Contains("No such file or directory"));
  }
  SECTION("cannot create files there, even as root") {
    CHECK_THAT(write_error(sim, "/proc/grainscale_snapshot.h5"), Contains("/proc/grainscale_snapshot.h5"));
    CHECK_FALSE(fs::exists("/proc/grainscale_snapshot.h5.tmp"));
  }
  SECTION("the tmp name is taken by a directory, which is not ours to remove") {
    fs::create_directories(good + ".tmp/keep");
    CHECK_THAT(write_error(sim, good), Contains(good));
    CHECK(fs::exists(good + ".tmp/keep"));
    fs::remove_all(good + ".tmp");
  }
  SECTION("rename fails after a complete write: the tmp file is removed") {
    const std::string blocked = dir / "blocked.h5";
    fs::create_directories(blocked + "/keep");
    CHECK_THAT(write_error(sim, blocked), Contains(blocked));
    CHECK_FALSE(fs::exists(blocked + ".tmp"));
    CHECK(fs::exists(blocked + "/keep"));
    fs::remove_all(blocked);
  }
  SECTION("wall names that cannot be group names are rejected when the wall is added") {
    Simulation twins(grain_materials(), sim.settings());
    twins.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 2);
    CHECK_THROWS_WITH(twins.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 1}, Vec3{0, 0, -1}), 2),
                      Contains("'floor'"));
    CHECK_THROWS_WITH(twins.add_wall("left/right", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 2),
                      Contains("'left/right'"));
  }

  CHECK(slurp(good) == before);
  CHECK_FALSE(fs::exists(good + ".tmp"));
  CHECK(open_hdf5_objects() == 0);
  // A good file is replaced atomically by a good one.
  write_snapshot(sim, good, {"second", 7});
  CHECK(read_snapshot(good).scenario_name == "second");
}

TEST_CASE("read_snapshot reports bad input naming the file and the object", "[dem][snapshot]") {
  const TempDir dir;
  SimulationSettings settings;
  settings.time_step = 1e-6;
  Simulation sim(grain_materials(), settings);
  for (int k = 0; k < 5; ++k) sim.add_sphere(k % 2, 0.001, {0.003 * k, 0, 0.01});
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 2);
  const std::string file = dir / "snap.h5";
  write_snapshot(sim, file, kInfo);  // Catch runs this again for every SECTION: each edits a fresh copy

  SECTION("missing file") {
    const std::string missing = dir / "missing.h5";
    CHECK_THAT(read_error(missing), Contains(missing) && Contains("does not exist"));
  }
  SECTION("not HDF5") {
    const std::string text = dir / "notes.h5";
    std::ofstream(text) << "not an HDF5 file\n";
    CHECK_THAT(read_error(text), Contains(text) && Contains("not an HDF5 file"));
  }
  SECTION("another layout version") {
    RawFile(file).set_int_attribute("layout_version", kSnapshotLayoutVersion + 1);
    CHECK_THAT(read_error(file), Contains(file) && Contains("layout_version") &&
                                     Contains(std::to_string(kSnapshotLayoutVersion + 1)));
  }
  SECTION("missing dataset") {
    RawFile(file).remove("/particles/radius");
    CHECK_THAT(read_error(file), Contains(file) && Contains("/particles/radius"));
  }
  SECTION("missing attribute") {
    {
      const RawFile raw(file);
      REQUIRE(H5Adelete(raw.id, "time") >= 0);
    }
    CHECK_THAT(read_error(file), Contains(file) && Contains("'time'"));
  }
  SECTION("inconsistent lengths") {
    {
      const RawFile raw(file);
      raw.remove("/particles/mass");
      raw.add_dataset("/particles/mass", 4);
    }
    CHECK_THAT(read_error(file), Contains(file) && Contains("/particles/mass") && Contains("4"));
  }
  SECTION("wrong shape") {
    {
      const RawFile raw(file);
      raw.remove("/particles/position");
      raw.add_dataset("/particles/position", 5);
    }
    CHECK_THAT(read_error(file), Contains(file) && Contains("/particles/position") && Contains("N x 3"));
  }
  SECTION("duplicate ids") {
    RawFile(file).replace_ids({0, 1, 2, 2, 4});
    CHECK_THAT(read_error(file), Contains(file) && Contains("/particles/id") && Contains("id 2 twice"));
  }
  SECTION("material index outside material_names") {
    {
      const RawFile raw(file);
      const hid_t d = H5Dopen2(raw.id, "/particles/material", H5P_DEFAULT);
      const std::int32_t bad[5] = {0, 1, 3, 0, 1};
      CHECK(H5Dwrite(d, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, bad) >= 0);
      H5Dclose(d);
    }
    CHECK_THAT(read_error(file), Contains(file) && Contains("/particles/material") && Contains("index 3"));
  }
  SECTION("rows not in id order (another writer) are sorted on reading") {
    const Snapshot before = read_snapshot(file);
    RawFile(file).replace_ids({40, 30, 20, 10, 0});
    const Snapshot after = read_snapshot(file);
    REQUIRE(after.id == std::vector<std::uint64_t>{0, 10, 20, 30, 40});
    for (std::size_t k = 0; k < 5; ++k) {
      CHECK(same_bits(after.position[k], before.position[4 - k]));
      CHECK(after.material[k] == before.material[4 - k]);
    }
  }
  SECTION("missing wall attribute") {
    {
      const RawFile raw(file);
      const hid_t g = H5Gopen2(raw.id, "/walls/floor", H5P_DEFAULT);
      REQUIRE(g >= 0);
      CHECK(H5Adelete(g, "orientation") >= 0);
      H5Gclose(g);
    }
    CHECK_THAT(read_error(file), Contains(file) && Contains("/walls/floor") && Contains("orientation"));
  }
  CHECK(open_hdf5_objects() == 0);
}

TEST_CASE("XDMF series references every snapshot at its time", "[dem][snapshot]") {
  const TempDir dir;
  SimulationSettings settings;
  settings.time_step = 1e-5;
  Simulation sim(grain_materials(), settings);
  for (int k = 0; k < 7; ++k) sim.add_sphere(0, 0.001, {0.003 * k, 0, 0.01});
  fs::create_directories(dir.path / "snapshots");

  std::vector<XdmfFrame> series;
  for (int s = 0; s < 3; ++s) {
    const std::string rel = "snapshots/snap_" + std::to_string(s) + ".h5";
    write_snapshot(sim, dir / rel, kInfo);
    series.push_back({sim.time(), rel, sim.particles().size(), {}});
    sim.run_steps(10);
  }
  const std::string xmf = dir / "series.xmf";
  write_xdmf_series(xmf, series);
  CHECK_FALSE(fs::exists(xmf + ".tmp"));

  const std::string text = slurp(xmf);
  CHECK_THAT(text, Contains("<Xdmf") && Contains("</Xdmf>") && Contains("CollectionType=\"Temporal\""));
  const std::regex grid("<Grid [^>]*GridType=\"Uniform\"");
  CHECK(std::distance(std::sregex_iterator(text.begin(), text.end(), grid), std::sregex_iterator()) == 3);
  const std::regex time("<Time Value=\"([^\"]+)\"");
  std::vector<double> times;
  for (auto m = std::sregex_iterator(text.begin(), text.end(), time); m != std::sregex_iterator(); ++m) {
    times.push_back(std::stod((*m)[1]));
  }
  REQUIRE(times.size() == 3);
  for (int s = 0; s < 3; ++s) {
    CHECK(times[s] == series[s].time);  // written with round-trip precision
    CHECK_THAT(text, Contains(series[s].h5 + ":/particles/position"));
  }
  CHECK_THAT(text, Contains("TopologyType=\"Polyvertex\"") && Contains("NumberOfElements=\"7\"") &&
                       Contains("Dimensions=\"7 3\""));
  for (const char* attr : {"radius", "material", "id", "velocity", "angular_velocity"}) {
    CHECK_THAT(text, Contains(std::string("<Attribute Name=\"") + attr + "\""));
  }

  // A bad entry throws and leaves the previous .xmf intact.
  series.push_back({std::numeric_limits<double>::quiet_NaN(), "snapshots/x.h5", 7, {}});
  CHECK_THROWS_AS(write_xdmf_series(xmf, series), std::invalid_argument);
  CHECK(slurp(xmf) == text);
}

}  // namespace grainscale::dem

namespace grainscale::dem {

TEST_CASE("Clumps round-trip: each sphere names its body, bodies carry pose, mass and shape", "[dem][snapshot][clump]") {
  const TempDir dir;
  SimulationSettings settings;
  settings.time_step = 1e-6;
  settings.gravity = {};
  Simulation sim(grain_materials(), settings);
  const Shape wheat = load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/wheat.yaml");
  sim.add_sphere(0, 0.001, {0.02, 0, 0});
  sim.add_clump(wheat, 1, 1300, {0, 0, 0.01}, axis_angle({0, 1, 0}, 0.4), {0.1, 0, 0}, {0, 0, 5});
  sim.run_steps(50);
  const std::string file = dir / "clump.h5";
  write_snapshot(sim, file, kInfo);
  const Snapshot s = read_snapshot(file);
  REQUIRE(s.shape_names == std::vector<std::string>{"wheat"});
  REQUIRE(s.body_id.size() == 2);
  CHECK(s.body_shape == std::vector<std::int32_t>{-1, 0});
  const Bodies& b = sim.bodies();
  for (std::size_t k = 0; k < 2; ++k) {  // the file is in id order, the bodies in slot order
    const std::size_t at = b.index_of(k);
    CHECK(s.body_mass[k] == b.mass[at]);
    CHECK(s.body_position[k] == b.x[at]);
    CHECK(s.body_velocity[k] == b.v[at]);
    CHECK(s.body_inertia[k] == b.inertia[at]);
    CHECK(s.body_orientation[k].w == b.q[at].w);
  }
  REQUIRE(s.body.size() == 8);
  double clump_mass = 0;
  for (std::size_t i = 0; i < 8; ++i) {
    if (s.body[i] == 1) clump_mass += s.mass[i];
  }
  CHECK_THAT(clump_mass, Catch::Matchers::WithinRel(b.mass[b.index_of(1)], 1e-12));  // sphere shares sum to the clump
}

TEST_CASE("A moving mesh wall is stored where it is, with its phase, and shown in the XDMF series",
          "[dem][snapshot][mesh]") {
  const TempDir dir;
  SimulationSettings settings;
  settings.time_step = 1e-5;
  Simulation sim(grain_materials(), settings);
  sim.add_sphere(0, 0.001, {0.1, 0.05, 0.01});
  sim.add_wall("tank", std::make_shared<MeshGeometry>(box_mesh({0, 0, 0}, {0.2, 0.1, 0.1}, {1, 1, 1, 1, 1, 0})), 1);
  PlatformTilt::Params tilt;
  tilt.amplitude = 0.3;
  tilt.start_level = false;  // holding at +A from t = 0
  sim.walls().back().set_motion({std::make_shared<PlatformTilt>(tilt), {-0.5, 0, 0}});
  sim.setup();
  sim.run_steps(10);
  const std::string h5 = dir / "snap.h5";
  write_snapshot(sim, h5, kInfo);

  const Snapshot snap = read_snapshot(h5);
  REQUIRE(snap.walls.size() == 1);
  CHECK(snap.walls[0].moving);
  CHECK(snap.walls[0].motion_phase == sim.walls()[0].phase());
  // A vertex of the stored mesh is the rest vertex turned by 0.3 rad about y through the pivot.
  const hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const hid_t d = H5Dopen2(f, "/walls/tank/vertices", H5P_DEFAULT);
  REQUIRE(d >= 0);
  std::vector<double> xyz;
  const auto& mesh = dynamic_cast<const MeshGeometry&>(sim.walls()[0].geometry()).mesh();
  xyz.resize(3 * mesh.vertices.size());
  REQUIRE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, xyz.data()) >= 0);
  H5Dclose(d);
  H5Fclose(f);
  const Vec3 expected = Vec3{-0.5, 0, 0} + rotate(axis_angle({0, 1, 0}, 0.3), mesh.vertices[0] - Vec3{-0.5, 0, 0});
  CHECK(norm(Vec3{xyz[0], xyz[1], xyz[2]} - expected) < 1e-14);

  const std::string xmf = dir / "series.xmf";
  write_xdmf_series(xmf, {{sim.time(), "snap.h5", sim.particles().size(), xdmf_meshes(sim)}});
  const std::string text = slurp(xmf);
  CHECK_THAT(text, Contains("CollectionType=\"Spatial\"") && Contains("TopologyType=\"Triangle\"") &&
                       Contains("snap.h5:/walls/tank/vertices"));
}

}  // namespace grainscale::dem
