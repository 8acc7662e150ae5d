// Checkpoint/restart: N steps in one go equal N/2 steps, a checkpoint, a restore into a fresh
// simulation built from the same scenario, and N/2 more - bit for bit, on 1 and 2 threads, with
// clumps, wall-contact histories on a moving mesh wall and a pour in progress (dem/checkpoint.hpp).
#include <hdf5.h>
#include <omp.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>

#include "barley_box_fixture.hpp"
#include "checkpoint_fixture.hpp"
#include "dem/checkpoint.hpp"
#include "dem/input_error.hpp"
#include "dem/scenario.hpp"
#include "dem/snapshot.hpp"
#include "parallel_everything.hpp"
#include "turning_box_fixture.hpp"

using namespace grainscale;
using namespace grainscale::dem;
using Catch::Matchers::Contains;

namespace {

constexpr std::uint64_t kSteps = 1600;

BuiltScenario started(const std::string& scenario) {
  BuiltScenario run = build(load_scenario(scenario));
  run.sim->setup();
  return run;
}

void advance(BuiltScenario& run, std::uint64_t steps) {
  for (std::uint64_t k = 0; k < steps; ++k) run.advance();
}

/// Wall contacts in use with a non-zero tangential history, over all spheres.
int wall_histories(const Simulation& sim) {
  const ForceField& f = sim.force_field();
  int n = 0;
  for (std::size_t i = 0; i < f.wall_counts().size(); ++i)
    for (int s = 0; s < f.wall_counts()[i]; ++s) n += norm2(f.wall_slot(i, s).history.shear) > 0;
  return n;
}

int pair_histories(const Simulation& sim) {
  int n = 0;
  for (const ContactHistory& h : sim.neighbors().histories()) n += norm2(h.shear) > 0 && norm2(h.rolling) > 0;
  return n;
}

/// bed() run 2 x `half` steps in one go, and `half` steps, through a checkpoint into a fresh bed(),
/// `half` more: both must end the same bit for bit. `restored(first, second)` checks what the restore
/// gave back, before the second half. Returns the list builds of the second half.
template <class Bed, class Restored>
std::size_t restarted_halfway(Bed bed, std::uint64_t half, Restored restored) {
  const testing::CheckpointTempDir dir;
  Simulation whole = bed();
  whole.run_steps(2 * half);
  Simulation first = bed();
  first.run_steps(half);
  write_checkpoint(dir / "half.h5", first);
  Simulation second = bed();
  restore_checkpoint(read_checkpoint(dir / "half.h5"), second);
  restored(first, second);
  const std::size_t builds = second.neighbors().builds();
  second.run_steps(half);
  testing::require_identical(whole, second);
  return second.neighbors().builds() - builds;
}

}  // namespace

TEST_CASE("A run restored from a checkpoint continues bit for bit, on 1 and 2 threads", "[dem][checkpoint]") {
  const testing::ParallelEverything guard;  // every loop parallel, however small
  const testing::CheckpointTempDir dir;
  const std::string scenario = testing::write_checkpoint_scenario(dir, 1.0);
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  INFO(threads << " threads");

  // Uninterrupted.
  BuiltScenario whole = started(scenario);
  advance(whole, kSteps);

  // Half, checkpoint, a fresh build of the same scenario, restore, the other half.
  const std::string file = dir / ("half_" + std::to_string(threads) + ".h5");
  {
    BuiltScenario first = started(scenario);
    advance(first, kSteps / 2);
    // What the checkpoint must carry is really there half-way: clumps, histories, a pour under way,
    // a wall that has moved.
    REQUIRE(first.sim->shape_names().size() == 1);
    REQUIRE(first.pouring());
    REQUIRE(first.pours[0].poured_count() > 0);
    REQUIRE(wall_histories(*first.sim) > 3);
    REQUIRE(pair_histories(*first.sim) > 3);
    REQUIRE(first.sim->walls()[0].pose().origin.x != 0);
    REQUIRE(first.sim->neighbors().builds() > 1);
    write_checkpoint(file, first);
  }
  BuiltScenario second = build(load_scenario(scenario));
  restore_checkpoint(read_checkpoint(file), second);
  const std::size_t spheres_at_restore = second.sim->particles().size();
  const std::size_t builds_at_restore = second.sim->neighbors().builds();
  advance(second, kSteps - kSteps / 2);

  // The second half poured more particles and rebuilt the list: the restored state was exercised.
  CHECK(second.sim->particles().size() > spheres_at_restore);
  CHECK(second.sim->neighbors().builds() > builds_at_restore);
  testing::require_identical(*whole.sim, *second.sim);
  CHECK(second.pours[0].poured_count() == whole.pours[0].poured_count());
  CHECK(second.rng.uniform() == whole.rng.uniform());
  omp_set_num_threads(2);
}

TEST_CASE("A run with a stray on its slack continues bit for bit from a checkpoint", "[dem][checkpoint][neighbor]") {
  // A grain thrown out of the box, 2 m below and falling: its slack (NeighborList::slack2) decides
  // when the list is rebuilt, so a restore must give it back exactly (it is rebuilt from the
  // positions at the build, which the checkpoint holds).
  const testing::ParallelEverything guard;
  auto bed = [] {
    Simulation sim = testing::barley_box(RollingModel::constant_torque, 6, 6, 5, 7);
    sim.add_sphere(0, 0.003, {0.02, 0.02, -2.0}, {0, 0, -10.0});
    return sim;
  };
  restarted_halfway(bed, 600, [](const Simulation& first, const Simulation& second) {
    REQUIRE_FALSE(first.neighbors().slack2().empty());
    CHECK(second.neighbors().slack2() == first.neighbors().slack2());
  });
}

TEST_CASE("A run whose spheres have skins of their own continues bit for bit from a checkpoint",
          "[dem][checkpoint][neighbor][skin]") {
  // A grain arriving at 2 m/s gets a thick skin of its own, the settled bed a thin one
  // (dem/adaptive_skin.hpp): each sphere's skin decides when the list is rebuilt, so a restore must
  // give them back exactly (/neighbors/skin).
  const testing::ParallelEverything guard;
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  auto bed = [] {
    Simulation sim = testing::barley_box(RollingModel::constant_torque, 6, 6, 5, 7);
    sim.run_steps(8000);  // settled: one thin skin for all
    sim.add_sphere(0, 0.003, {0.02, 0.02, 0.08}, {0, 0, -2.0});
    return sim;
  };
  const std::size_t builds = restarted_halfway(bed, 200, [](const Simulation& first, const Simulation& second) {
    REQUIRE_FALSE(first.neighbors().skins().empty());
    CHECK(second.neighbors().skins() == first.neighbors().skins());
    CHECK(second.neighbors().slack2() == first.neighbors().slack2());
  });
  CHECK(builds > 0);  // the restored skins were used
  omp_set_num_threads(2);
}

TEST_CASE("A list measured in a turning box's frame continues bit for bit from a checkpoint",
          "[dem][checkpoint][neighbor][frame]") {
  // The box's pose at the build (/neighbors/frame_at_build, dem/list_frame.hpp) decides when the list
  // is rebuilt, so a restore must give it back exactly.
  const testing::ParallelEverything guard;
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  // The bed settled in the turning box (the list then in the box's frame), once for every bed().
  const testing::CheckpointTempDir dir;
  {
    Simulation sim = testing::turning_box(SimulationSettings{}, 0.0, 0.26);
    sim.setup();
    sim.run_steps(static_cast<std::uint64_t>(0.25 / sim.dt()));
    write_checkpoint(dir / "settled.h5", sim);
  }
  auto bed = [&] {
    Simulation sim = testing::turning_box(SimulationSettings{}, 0.0, 0.26);
    restore_checkpoint(read_checkpoint(dir / "settled.h5"), sim);
    return sim;
  };
  const std::size_t builds = restarted_halfway(bed, 1500, [](const Simulation& first, const Simulation& second) {
    REQUIRE(first.neighbors().frame().in_wall());
    CHECK(second.neighbors().frame().wall == first.neighbors().frame().wall);
    const WallPose &a = first.neighbors().frame().at_build, &b = second.neighbors().frame().at_build;
    CHECK(std::memcmp(&a.origin, &b.origin, sizeof(Vec3)) == 0);
    CHECK(std::memcmp(&a.orientation, &b.orientation, sizeof(Quat)) == 0);
  });
  CHECK(builds > 0);
  omp_set_num_threads(2);
}

TEST_CASE("Restoring a checkpoint and writing it again gives the same bytes", "[dem][checkpoint]") {
  // Everything stored is read back as it was (no field forgotten on either side).
  const testing::CheckpointTempDir dir;
  const std::string scenario = testing::write_checkpoint_scenario(dir, 1.0);
  BuiltScenario first = started(scenario);
  advance(first, 300);
  RunRecord record;
  record.scenario = scenario_fingerprint(load_scenario(scenario));
  record.next_snapshot = 0.0125;
  record.snapshot_time = {0, 0.01};
  record.snapshot_file = {"snapshots/snap_000000.h5", "snapshots/snap_000001.h5"};
  record.snapshot_particles = {100, 120};
  record.wall_seconds = 12.5;
  record.warned_stability = true;
  write_checkpoint(dir / "a.h5", first, &record);
  BuiltScenario second = build(load_scenario(scenario));
  Checkpoint c = read_checkpoint(dir / "a.h5");
  CHECK(c.code_version == checkpoint_code_version());
  CHECK(c.run.scenario == record.scenario);
  CHECK(c.run.snapshot_file == record.snapshot_file);
  restore_checkpoint(std::move(c), second);
  write_checkpoint(dir / "b.h5", second, &record);
  CHECK(testing::slurp_file(dir / "a.h5") == testing::slurp_file(dir / "b.h5"));
  // A checkpoint of a bare simulation (no scenario) round-trips too.
  write_checkpoint(dir / "bare.h5", *first.sim);
  Simulation copy = *build(load_scenario(scenario), false).sim;
  restore_checkpoint(read_checkpoint(dir / "bare.h5"), copy);
  write_checkpoint(dir / "bare2.h5", copy);
  CHECK(testing::slurp_file(dir / "bare.h5") == testing::slurp_file(dir / "bare2.h5"));
}

TEST_CASE("Bad checkpoints and mismatched simulations are refused, naming the file", "[dem][checkpoint]") {
  const testing::CheckpointTempDir dir;
  const std::string scenario = testing::write_checkpoint_scenario(dir, 1.0);
  BuiltScenario run = started(scenario);
  advance(run, 50);
  const std::string good = dir / "good.h5";
  write_checkpoint(good, run);

  SECTION("missing file, not HDF5, a snapshot") {
    CHECK_THROWS_WITH(read_checkpoint(dir / "none.h5"), Contains("none.h5") && Contains("does not exist"));
    std::ofstream(dir / "text.h5") << "not hdf5";
    CHECK_THROWS_WITH(read_checkpoint(dir / "text.h5"), Contains("text.h5") && Contains("not an HDF5 file"));
    write_snapshot(*run.sim, dir / "snap.h5", {"x", 1});
    CHECK_THROWS_WITH(read_checkpoint(dir / "snap.h5"), Contains("snap.h5") && Contains("not a grainscale checkpoint"));
  }
  SECTION("a dataset missing or of the wrong shape") {
    for (const char* victim : {"/neighbors/history", "/particles/position_at_build"}) {
      const std::string broken = dir / "broken.h5";
      std::filesystem::copy_file(good, broken, std::filesystem::copy_options::overwrite_existing);
      const hid_t f = H5Fopen(broken.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
      REQUIRE(f >= 0);
      REQUIRE(H5Ldelete(f, victim, H5P_DEFAULT) >= 0);
      H5Fclose(f);
      CHECK_THROWS_AS(read_checkpoint(broken), InputError);
      CHECK_THROWS_WITH(read_checkpoint(broken), Contains("broken.h5") && Contains(victim));
    }
  }
  SECTION("another simulation: other walls or materials") {
    Simulation other(run.sim->materials(), run.sim->settings());
    CHECK_THROWS_WITH(restore_checkpoint(read_checkpoint(good), other), Contains("good.h5") && Contains("walls [box, shelf]"));
  }
  SECTION("an inconsistent state leaves the simulation as it was") {
    Checkpoint c = read_checkpoint(good);
    REQUIRE(c.simulation.neighbor_partner.size() > 0);
    c.simulation.neighbor_partner[0] = static_cast<std::uint32_t>(c.simulation.particles.size());
    BuiltScenario fresh = started(scenario);
    const std::vector<Vec3> before = fresh.sim->bodies().x;
    CHECK_THROWS_WITH(restore_checkpoint(std::move(c), fresh), Contains("good.h5") && Contains("neighbour list"));
    CHECK(fresh.sim->bodies().x == before);
    fresh.advance();  // still usable
  }
  SECTION("rows of the neighbour list reaching past its entries (found by fuzzing)") {
    Checkpoint c = read_checkpoint(good);
    REQUIRE(c.simulation.neighbor_start.size() > 2);
    c.simulation.neighbor_start[1] = 1u << 30;  // row 0 would read far past the entries
    BuiltScenario fresh = started(scenario);
    CHECK_THROWS_WITH(restore_checkpoint(std::move(c), fresh), Contains("row starts decrease"));
  }
  SECTION("particles flung beyond any sensible domain stop as a blow-up (found by fuzzing)") {
    Checkpoint c = read_checkpoint(good);
    c.simulation.bodies.x[0] = {1e308, 0, 0};
    c.simulation.bodies.x[1] = {-1e308, 0, 0};
    BuiltScenario fresh = build(load_scenario(scenario));
    restore_checkpoint(std::move(c), fresh);  // finite: a valid state, however absurd
    CHECK_THROWS_AS(fresh.sim->step(), BlowUp);
  }
  SECTION("a scenario run needs the pours and random numbers") {
    BuiltScenario fresh = build(load_scenario(scenario));
    write_checkpoint(dir / "bare.h5", *run.sim);
    CHECK_THROWS_WITH(restore_checkpoint(read_checkpoint(dir / "bare.h5"), fresh), Contains("not a scenario run"));
  }
}

TEST_CASE("A blown-up state is never written over a good checkpoint", "[dem][checkpoint]") {
  const testing::CheckpointTempDir dir;
  const std::string scenario = testing::write_checkpoint_scenario(dir, 1.0);
  BuiltScenario run = started(scenario);
  advance(run, 150);
  const std::string file = dir / "checkpoint.h5";
  write_checkpoint(file, run);
  const std::string before = testing::slurp_file(file);
  // A NaN creeps into the mass of a sphere touching a wall: the next step's forces go non-finite and
  // the blow-up check stops it, leaving the state half-stepped.
  Simulation& sim = *run.sim;
  std::size_t touching = 0;
  while (touching < sim.force_field().wall_counts().size() && sim.force_field().wall_counts()[touching] == 0) ++touching;
  REQUIRE(touching < sim.particles().size());
  sim.particles().mass[touching] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(sim.step(), BlowUp);
  CHECK_THROWS_WITH(write_checkpoint(file, run), Contains(file) && Contains("non-finite") && Contains("kept"));
  CHECK(testing::slurp_file(file) == before);
  CHECK_FALSE(std::filesystem::exists(file + ".tmp"));
  // Nor is such a state restored from a (hand-made) checkpoint.
  Checkpoint c = read_checkpoint(file);
  c.simulation.bodies.v[3].x = std::numeric_limits<double>::quiet_NaN();
  BuiltScenario fresh = build(load_scenario(scenario));
  CHECK_THROWS_WITH(restore_checkpoint(std::move(c), fresh), Contains("body 3 has a non-finite state"));
}

TEST_CASE("Bodies are numbered in their spheres' order, and no result depends on that order", "[dem][checkpoint]") {
  // dem/bodies.hpp: bodies are renumbered with their spheres so that a step's body and sphere loops
  // walk memory in the same order. That order is a layout choice only: checkpoints store the bodies
  // in id order, and a saved state whose bodies come in any other order (here reversed) is accepted
  // and continues exactly as the original, body by body. (That the step itself
  // does not depend on the order was checked when it was introduced: the clump bed ended on the same
  // fingerprint with and without the renumbering, docs/performance.md.)
  const testing::CheckpointTempDir dir;
  const std::string scenario = testing::write_checkpoint_scenario(dir, 1.0);
  BuiltScenario run = started(scenario);
  advance(run, 400);
  const Bodies& b = run.sim->bodies();
  const Particles& p = run.sim->particles();
  REQUIRE(b.size() > 50);
  // First spheres in slot order meet their bodies in index order; ids are a permutation.
  std::uint32_t next = 0;
  for (std::size_t s = 0; s < p.size(); ++s) {
    REQUIRE(p.body[s] <= next);
    if (p.body[s] == next) ++next;
  }
  CHECK(next == b.size());
  std::vector<std::uint64_t> ids(b.id);
  std::sort(ids.begin(), ids.end());
  for (std::size_t k = 0; k < ids.size(); ++k) REQUIRE(ids[k] == k);
  bool renumbered = false;
  for (std::size_t k = 0; k < b.size(); ++k) renumbered |= b.id[k] != k;
  CHECK(renumbered);  // (else this test would not test anything)

  const std::string file = dir / "state.h5";
  write_checkpoint(file, run);
  Checkpoint c = read_checkpoint(file);
  SimulationState& s = c.simulation;
  const std::size_t nb = s.bodies.size();
  for (std::size_t k = 0; k < nb; ++k) REQUIRE(s.bodies.id[k] == k);  // the file is in id order
  std::vector<std::uint32_t> reversed(nb);
  for (std::size_t k = 0; k < nb; ++k) reversed[k] = static_cast<std::uint32_t>(nb - 1 - k);
  s.bodies.permute(reversed);
  for (auto& k : s.particles.body) k = static_cast<std::uint32_t>(nb - 1 - k);
  s.bodies.sphere_start.clear(), s.bodies.sphere_slot.clear();  // (rebuilt on restore)
  BuiltScenario other = build(load_scenario(scenario));
  restore_checkpoint(std::move(c), other);
  advance(run, 600);
  advance(other, 600);
  const Bodies &ba = run.sim->bodies(), &bo = other.sim->bodies();
  REQUIRE(ba.size() == bo.size());
  for (std::size_t k = 0; k < ba.size(); ++k) {
    const std::size_t j = bo.index_of(ba.id[k]);
    REQUIRE(std::memcmp(&ba.x[k], &bo.x[j], sizeof(Vec3)) == 0);
    REQUIRE(std::memcmp(&ba.q[k], &bo.q[j], sizeof(Quat)) == 0);
    REQUIRE(std::memcmp(&ba.L[k], &bo.L[j], sizeof(Vec3)) == 0);
  }
}
