// The adaptive Verlet skin (dem/adaptive_skin.hpp): its rule, its bounds, that a bed coming to rest
// gets a thin skin and a fast arrival the thickest (its own: the bed keeps the thin one), that the
// list stays exact at every step
// while the skin changes (contacts against an O(N^2) search), and that a fixed time.skin is kept.
#include <omp.h>

#include <algorithm>

#include <catch2/catch.hpp>

#include "all_contacts_search.hpp"
#include "barley_box_fixture.hpp"
#include "checkpoint_fixture.hpp"
#include "dem/adaptive_skin.hpp"
#include "dem/checkpoint.hpp"
#include "parallel_everything.hpp"

using namespace grainscale::dem;

namespace {

using grainscale::dem::testing::overlapping_pairs;

/// A small barley box (4 x 4 x nz spheres) run under a fixed skin, and the same state restored
/// (through a checkpoint file) into a box whose settings are `then`.
struct FixedThenRestored {
  Simulation fixed, restored;
  FixedThenRestored(int nz, double skin, std::uint64_t steps, SimulationSettings then)
      : fixed(testing::barley_box(RollingModel::constant_torque, 4, 4, nz, 8, with_skin(skin))),
        restored(testing::barley_box(RollingModel::constant_torque, 4, 4, nz, 8, then)) {
    fixed.run_steps(steps);
    const testing::CheckpointTempDir dir;
    write_checkpoint(dir / "state.h5", fixed);
    restore_checkpoint(read_checkpoint(dir / "state.h5"), restored);
  }
  static SimulationSettings with_skin(double skin) {
    SimulationSettings st;
    st.skin = skin;
    return st;
  }
};

double largest_radius(const Particles& p) {
  double r = 0;
  for (double x : p.radius) r = std::max(r, x);
  return r;
}

}  // namespace

TEST_CASE("The adaptive skin lasts kSteps steps at the fastest speed, between its bounds", "[dem][neighbor][skin]") {
  const double dt = 1e-5, skin_max = 6e-4;
  // The list is stale after skin / 2 of travel: kSteps steps at v need skin = 2 kSteps v dt.
  const double v = GENERATE(0.05, 0.2, 0.5);
  const double skin = AdaptiveSkin::choose(v, dt, skin_max);
  CHECK(skin == Approx(2 * AdaptiveSkin::kSteps * v * dt).epsilon(1e-14));
  CHECK(0.5 * skin / (v * dt) == Approx(AdaptiveSkin::kSteps));
  // At rest the list still needs a skin; a stampede gets the fixed skin grainscale used before.
  CHECK(AdaptiveSkin::choose(0, dt, skin_max) == AdaptiveSkin::kMinFraction * skin_max);
  CHECK(AdaptiveSkin::choose(100, dt, skin_max) == skin_max);
  // A sphere faster than the common speed gets a skin of its own that lasts kOwnSteps, twice as long.
  const double u = 0.5 * v;  // (within the bounds for every v above)
  CHECK(0.5 * AdaptiveSkin::choose_own(u, dt, skin_max) / (u * dt) == Approx(AdaptiveSkin::kOwnSteps));
  CHECK(AdaptiveSkin::kOwnSteps == 2 * AdaptiveSkin::kSteps);
  CHECK(AdaptiveSkin::choose_own(100, dt, skin_max) == skin_max);
  // Rebuilt early only for a skin under half the present one.
  CHECK(AdaptiveSkin::shrink(4e-4, 1.9e-4));
  CHECK(!AdaptiveSkin::shrink(4e-4, 2.1e-4));
}

TEST_CASE("A settling bed's skin thins as it comes to rest, a fast arrival thickens it, and every contact is found",
          "[dem][neighbor][skin]") {
  const testing::ParallelEverything guard;
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  Simulation sim = testing::barley_box(RollingModel::constant_torque, 6, 6, 5, 3);
  sim.setup();
  const double skin_max = 0.2 * largest_radius(sim.particles());
  double thickest = 0;
  std::size_t skins_seen = 0;
  double last = sim.skin();
  // Every step: the contacts the force loop found are exactly the overlapping pairs, whatever the
  // skin of the list they came from (a list built with too thin a skin, or kept too long, misses some).
  for (int step = 0; step < 6000; ++step) {
    sim.run_steps(1);
    REQUIRE(sim.diagnostics().contacts == overlapping_pairs(sim.particles()));
    thickest = std::max(thickest, sim.skin());
    skins_seen += sim.skin() != last;
    last = sim.skin();
  }
  INFO("skin " << sim.skin() << " m at the end, thickest " << thickest << " m, " << skins_seen << " changes, "
               << sim.neighbors().builds() << " builds");
  CHECK(skins_seen >= 3);
  CHECK(thickest <= skin_max);
  CHECK(thickest > 4 * sim.skin());
  // Nearly at rest after 6000 steps: a thin skin, not below the bound.
  CHECK(sim.skin() < 0.1 * skin_max);
  CHECK(sim.skin() >= AdaptiveSkin::kMinFraction * skin_max);

  // A grain dropped in at 2 m/s: its arrival is a build, sized for its speed (here the bound).
  const std::size_t builds = sim.neighbors().builds();
  sim.add_sphere(0, 0.003, {0.02, 0.02, 0.08}, {0, 0, -2.0});
  sim.run_steps(1);
  CHECK(sim.neighbors().builds() == builds + 1);
  CHECK(sim.skin() == Approx(std::min(skin_max, 2 * AdaptiveSkin::kSteps * 2.0 * sim.dt())).epsilon(0.02));
  // That skin is its own (and its neighbours'): the bed keeps its thin common skin, so its lists
  // stay as short as they were.
  REQUIRE_FALSE(sim.neighbors().skins().empty());
  CHECK(sim.neighbors().smallest_skin() < 0.2 * sim.skin());
  const std::vector<double>& skins = sim.neighbors().skins();
  CHECK(std::count(skins.begin(), skins.end(), sim.neighbors().smallest_skin()) > 150);
  // Every contact found while it falls into the bed and the struck grains move off.
  for (int step = 0; step < 3000; ++step) {
    sim.run_steps(1);
    REQUIRE(sim.diagnostics().contacts == overlapping_pairs(sim.particles()));
  }
  omp_set_num_threads(2);
}

TEST_CASE("A bed at rest under a thick skin is rebuilt with a thin one within kCheckEvery steps",
          "[dem][neighbor][skin]") {
  // A list that never goes stale would keep its build's skin for ever: the bed settles under a fixed
  // skin of 0.2 r_max, then continues with the adaptive one.
  FixedThenRestored run(3, 6e-4, 30000, SimulationSettings{});
  Simulation &fixed = run.fixed, &adaptive = run.restored;
  REQUIRE(adaptive.skin() == 6e-4);
  const std::size_t builds = adaptive.neighbors().builds();
  adaptive.run_steps(AdaptiveSkin::kCheckEvery);
  fixed.run_steps(AdaptiveSkin::kCheckEvery);
  CHECK(fixed.neighbors().builds() == builds);  // at rest: the thick list is never stale
  CHECK(adaptive.neighbors().builds() == builds + 1);
  CHECK(adaptive.skin() < 0.5 * 6e-4);
}

TEST_CASE("A fixed skin is kept, and a state restored under another fixed skin takes it at the next step",
          "[dem][neighbor][skin]") {
  // The same state restored under time.skin 2e-4: the list is rebuilt with it at once.
  FixedThenRestored run(4, 4e-4, 3000, FixedThenRestored::with_skin(2e-4));
  const Simulation& fixed = run.fixed;
  Simulation& other = run.restored;
  CHECK(fixed.skin() == 4e-4);
  CHECK(fixed.neighbors().skin() == 4e-4);
  const std::size_t builds = other.neighbors().builds();
  other.run_steps(1);
  CHECK(other.neighbors().builds() == builds + 1);
  CHECK(other.neighbors().skin() == 2e-4);
}
