// The neighbour list measured in a moving container's frame (dem/list_frame.hpp): a bed carried by
// its box travels far in the world and hardly at all in the box, so its list lasts; any rigid frame
// keeps the list exact, so the contacts found must be those a search over every pair finds.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <memory>
#include <numbers>

#include "dem/list_frame.hpp"
#include "dem/motion/sinusoidal_motion.hpp"
#include "all_contacts_search.hpp"
#include "turning_box_fixture.hpp"

using namespace grainscale::dem;

namespace {

using testing::overlapping_pairs;
using testing::turning_box;
using testing::wall_contacts;

}  // namespace

TEST_CASE("A frame shift carries a point fixed in the frame from its place at the build to its place now",
          "[dem][neighbors][frame]") {
  WallPose then, now;
  then.origin = {0.3, -0.2, 0.1};
  then.orientation = normalized(Quat{0.9, 0.1, -0.3, 0.2});
  now.origin = {0.25, -0.1, 0.4};
  now.orientation = normalized(Quat{0.7, -0.2, 0.4, 0.5});
  const FrameShift g = FrameShift::between(then, now);
  for (const Vec3 y : {Vec3{0, 0, 0}, Vec3{0.1, -0.3, 0.7}, Vec3{-2, 1, 0.5}}) {
    CHECK(norm(g(then.to_world(y)) - now.to_world(y)) < 1e-15);
  }
  // A shift keeps distances (it is rigid), and the world's does nothing at all, bit for bit.
  const Vec3 a{0.1, 0.2, 0.3}, b{-0.4, 0.5, 0.05};
  CHECK(std::abs(norm(g(a) - g(b)) - norm(a - b)) < 1e-15);
  const Vec3 c{0.1 / 3, 1.0 / 7, -2.0 / 9};
  const Vec3 same = ListFrame{}.shift_to(now)(c);
  CHECK((same.x == c.x && same.y == c.y && same.z == c.z));
}

TEST_CASE("A bed carried by a turning box keeps its list measured in the box's frame, and finds every contact",
          "[dem][neighbors][frame][motion][walls]") {
  // The box turns from the start; the bed settles in it within 0.25 s and then rides along (the 99th
  // percentile of the spheres' speeds: millimetres a second in the box, 0.08 m/s in the world). Measured
  // in the world, every sphere travels skin/2 within a few dozen steps; measured in the box's frame
  // only the bed's own creep counts. Either way the list must hold every pair that touches, and the
  // near-wall masks every sphere that touches a wall: at every step the contacts the force loop finds
  // are those a search over all pairs and walls finds.
  const double rate = 0.26, settle = 0.25, riding = 0.12;
  struct Outcome {
    std::size_t builds = 0, worst_miss = 1, contacts = 0;
    double entries = 0, skin = 0;  // list entries and common skin (m), averaged over the steps
    int frame_wall = -2;
  };
  auto run = [&](SimulationSettings::ListFrameChoice choice) {
    SimulationSettings st;
    st.list_frame = choice;
    Simulation sim = turning_box(st, 0.0, rate);
    sim.setup();
    sim.run_steps(static_cast<std::uint64_t>(settle / sim.dt()));
    Outcome o;
    const std::size_t before = sim.neighbors().builds();
    o.worst_miss = 0;
    const int steps = static_cast<int>(riding / sim.dt());
    for (int s = 0; s < steps; ++s) {
      sim.step();
      const std::size_t pairs = overlapping_pairs(sim.particles()), walls = wall_contacts(sim, 0);
      const ForceDiagnostics& d = sim.diagnostics();
      o.worst_miss = std::max({o.worst_miss, pairs > d.contacts ? pairs - d.contacts : d.contacts - pairs,
                               walls > d.wall_contacts ? walls - d.wall_contacts : d.wall_contacts - walls});
      o.contacts = std::max(o.contacts, pairs + walls);
      o.entries += static_cast<double>(sim.neighbors().entries()) / steps;
      o.skin += sim.neighbors().smallest_skin() / steps;
    }
    o.builds = sim.neighbors().builds() - before;
    o.frame_wall = sim.neighbors().frame().wall;
    // The bed rode with the box: none left it.
    const WallPose& box = sim.walls()[0].pose();
    double top = 0;
    for (std::size_t i = 0; i < sim.particles().size(); ++i) top = std::max(top, box.to_body(sim.particles().x[i]).z);
    CHECK(top < 0.06);
    return o;
  };
  const Outcome in_box = run(SimulationSettings::ListFrameChoice::automatic);
  const Outcome in_world = run(SimulationSettings::ListFrameChoice::world);
  INFO("while riding, in the box's frame and in the world's: " << in_box.builds << " and " << in_world.builds
                                                              << " list builds, " << in_box.entries << " and "
                                                              << in_world.entries << " entries, common skins "
                                                              << in_box.skin << " and " << in_world.skin << " m");
  CHECK(in_box.frame_wall == 0);  // the box's frame, chosen at the builds while it turned
  CHECK(in_world.frame_wall == -1);
  CHECK(in_box.worst_miss == 0);
  CHECK(in_world.worst_miss == 0);
  CHECK(in_box.contacts > 700);  // a bed at rest in its box: every sphere touching several
  // Measured in the box, the common skin is near the floor (dem/adaptive_skin.hpp), an eighth of the
  // world's (3.5e-5 against 2.8e-4 m), and the list holds 14 % fewer entries. (Builds are as frequent: the few spheres that still move in the
  // box get skins of their own that last ~40 steps, as every sphere's does in the world.)
  CHECK(in_box.skin < 0.5 * in_world.skin);
  CHECK(in_box.builds <= in_world.builds + in_world.builds / 10);
  CHECK(in_box.entries < 0.97 * in_world.entries);
}

TEST_CASE("A bed swung hard, its list's frame switching between the world's and the box's, finds every contact",
          "[dem][neighbors][frame][motion][walls]") {
  // The loop study's swing (+-35 deg at 0.5 Hz about an axis 0.8 m from the box, the box at up to
  // 1.5 m/s): the bed rides with the box, then slides and flows inside it as it turns over, and the
  // frame chosen at the builds changes with that. At every step the pair and wall contacts found
  // must be those a search over all of them finds.
  Simulation sim = turning_box(SimulationSettings{}, 0.0, 0.0);
  std::array<SinusoidalMotion::Dof, 6> swing{};
  swing[1] = {35 * std::numbers::pi / 180, 0.5, 0};  // pitch about y
  sim.walls()[0].set_motion({std::make_shared<SinusoidalMotion>(swing), {-0.8, 0.02, 0.0}});
  sim.setup();
  std::size_t worst_miss = 0, in_box = 0, steps = 0;
  while (sim.time() < 0.7) {
    sim.step();
    ++steps;
    const std::size_t pairs = overlapping_pairs(sim.particles()), walls = wall_contacts(sim, 0);
    const ForceDiagnostics& d = sim.diagnostics();
    worst_miss = std::max({worst_miss, pairs > d.contacts ? pairs - d.contacts : d.contacts - pairs,
                           walls > d.wall_contacts ? walls - d.wall_contacts : d.wall_contacts - walls});
    in_box += sim.neighbors().frame().wall == 0;
  }
  INFO(steps << " steps, " << in_box << " with the list in the box's frame");
  CHECK(worst_miss == 0);
  CHECK(in_box > steps / 10);          // both frames were used
  CHECK(in_box < steps - steps / 10);
}

TEST_CASE("A bed in a box at rest is measured in the world: the same numbers as the world's frame, bit for bit",
          "[dem][neighbors][frame]") {
  // Before the platform starts, the box's frame is the world's and the choice keeps to the world, so
  // a scenario with a motion yet to start runs exactly as it did before frames were chosen.
  auto run = [](SimulationSettings::ListFrameChoice choice) {
    SimulationSettings st;
    st.list_frame = choice;
    auto sim = std::make_unique<Simulation>(turning_box(st, 10.0, 0.26));
    sim->setup();
    sim->run_steps(1500);
    return sim;
  };
  const auto a = run(SimulationSettings::ListFrameChoice::automatic);
  const auto b = run(SimulationSettings::ListFrameChoice::world);
  CHECK(!a->neighbors().frame().in_wall());
  CHECK(a->neighbors().builds() == b->neighbors().builds());
  bool same = true;
  for (std::size_t i = 0; i < a->particles().size(); ++i) {
    const Vec3 x = a->particles().x[i], y = b->particles().x[i];
    same = same && x.x == y.x && x.y == y.y && x.z == y.z;
  }
  CHECK(same);
}

TEST_CASE("A wall fixed in the world, met by a bed its box lifts, is found at every step",
          "[dem][neighbors][frame][motion][walls]") {
  // The list measured in the box's frame, in which the bar moves towards the bed: the near-wall masks
  // must follow it there (made again once some point of the spheres' region, in the box's frame,
  // has moved half a skin in the bar's, ForceField::walls_where_found), so that at every step the
  // wall contacts found are those a search over all spheres and walls finds.
  Simulation sim = turning_box(SimulationSettings{}, 0.0, -0.6, true);  // rising at 0.3 m/s
  sim.setup();
  sim.run_steps(static_cast<std::uint64_t>(0.2 / sim.dt()));
  std::size_t worst_miss = 0, most = 0, in_box = 0;
  const int steps = static_cast<int>(0.05 / sim.dt());
  for (int s = 0; s < steps; ++s) {
    sim.step();
    const std::size_t expected = wall_contacts(sim, 0) + wall_contacts(sim, 1);
    const std::size_t found = sim.diagnostics().wall_contacts;
    worst_miss = std::max(worst_miss, expected > found ? expected - found : found - expected);
    most = std::max(most, wall_contacts(sim, 1));
    in_box += sim.neighbors().frame().wall == 0;
  }
  INFO(steps << " steps, " << in_box << " of them with the list in the box's frame, up to " << most
             << " contacts with the bar");
  CHECK(worst_miss == 0);
  CHECK(most > 3);  // the bed met the bar
  CHECK(2 * in_box > static_cast<std::size_t>(steps));  // mostly in the box's frame
}

TEST_CASE("The near-wall masks expire before a wall moving in the list's frame has gone half a skin towards any sphere",
          "[dem][neighbors][frame][motion][walls]") {
  // ForceField::walls_where_found judges how far the bar has moved against the bed by the corners of
  // the box around the spheres, taken in the list's frame. Here the walls alone are moved on from a
  // step's end (the spheres carried rigidly with the box, as a bed at rest in it would be), and
  // while the masks still hold, no sphere they leave out of the bar's reach may have moved more
  // than the margin, ForceField::kMovingWallMargin skins, against the bar. The box sits 0.5 m aside
  // of the world's origin and turns about a pivot 0.45 m further: a region taken in the world's
  // coordinates instead of the box's would sit by the pivot, where the turn hardly moves anything,
  // and hold the masks five times too long.
  const double start = GENERATE(0.1, 0.25);
  Simulation sim = turning_box(SimulationSettings{}, 0.0, -0.6, true);  // rising at 0.3 m/s
  sim.setup();
  sim.run_steps(static_cast<std::uint64_t>(start / sim.dt()));
  for (int s = 0; s < 1000 && sim.neighbors().frame().wall != 0; ++s) sim.step();
  REQUIRE(sim.neighbors().frame().wall == 0);  // the list in the box's frame
  const Particles& p = sim.particles();
  const WallPose box_then = sim.walls()[0].pose();
  const double margin = ForceField::kMovingWallMargin * sim.neighbors().skin();
  REQUIRE(sim.force_field().near_wall_masks(sim.walls(), sim.neighbors(), p.size()) != nullptr);
  std::vector<Wall> walls = sim.walls();
  double worst = 0;  // the largest shift of a sphere left out of the bar's reach, in margins
  bool expired = false;
  for (int k = 1; k <= 400 && !expired; ++k) {
    const double t = sim.time() + k * sim.dt() / 8;
    for (Wall& w : walls) w.move_to(t);
    const std::uint32_t* masks = sim.force_field().near_wall_masks(walls, sim.neighbors(), p.size());
    if (masks == nullptr) {
      expired = true;
      break;
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (masks[i] >> 1 & 1u) continue;  // flagged near the bar
      const Vec3 now = walls[0].pose().to_world(box_then.to_body(p.x[i]));  // the bar is fixed in the world
      worst = std::max(worst, norm(now - p.x[i]) / margin);
    }
  }
  INFO("skin " << sim.neighbors().skin() << " m; worst shift of a sphere out of the bar's reach " << worst << " margins");
  CHECK(expired);
  CHECK(worst <= 1.0);
  CHECK(worst > 0.5);  // the masks held until the bar had moved most of the margin
}
