// Adding particles to a running simulation (pouring): existing contacts keep their history.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "dem/input_error.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/plane.hpp"

using namespace grainscale;
using namespace grainscale::dem;

namespace {

/// A small pyramid on a floor, in a channel: two spheres side by side and one on top, with gravity
/// tilted by 4 degrees across the pyramid's plane. The top sphere is held only by friction in its two pair
/// contacts, so their tangential springs (histories) carry load.
Simulation pyramid() {
  MaterialTable mt;
  mt.add({"grain", 1380, 2.6e7, 0.3});
  mt.add({"floor", 1190, 7.97e8, 0.38});
  mt.set_pair(0, 0, {0.3, 0.6, 0.1, true});
  mt.set_pair(0, 1, {0.3, 0.6, 0.1, true});
  SimulationSettings st;
  const double a = 4 * M_PI / 180;  // tan 4 deg < mu_r: the bottom pair does not roll away
  st.gravity = {0, 9.81 * std::sin(a), -9.81 * std::cos(a)};
  Simulation sim(mt, st);
  const double r = 0.003;
  sim.add_sphere(0, r, {-r, 0, r});
  sim.add_sphere(0, r, {r, 0, r});
  sim.add_sphere(0, r, {0, 0, r + std::sqrt(3.0) * r});
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
  // Side walls keep the bottom pair from being rolled apart by the top sphere.
  sim.add_wall("left", std::make_shared<PlaneGeometry>(Vec3{-2 * r, 0, 0}, Vec3{1, 0, 0}), 1);
  sim.add_wall("right", std::make_shared<PlaneGeometry>(Vec3{2 * r, 0, 0}, Vec3{-1, 0, 0}), 1);
  sim.run_steps(static_cast<std::uint64_t>(0.5 / 2e-5));  // settle into static friction
  return sim;
}

}  // namespace

TEST_CASE("Particles added mid-run leave the histories of existing contacts intact", "[dem][insertion]") {
  Simulation with = pyramid();
  Simulation without = with;  // same state
  REQUIRE(with.diagnostics().contacts >= 2);
  REQUIRE(with.diagnostics().wall_contacts >= 2);
  REQUIRE(norm(with.bodies().v[with.bodies().index_of(2)]) < 1e-4);  // at rest
  const std::uint64_t builds = with.neighbors().builds();
  with.add_sphere(0, 0.003, {0.5, 0.5, 0.2});  // far away: it cannot touch the pair
  for (int s = 0; s < 2000; ++s) {
    with.step();
    without.step();
  }
  CHECK(with.neighbors().builds() > builds);  // the list was rebuilt for the newcomer
  // The pyramid moves exactly as without the newcomer. With the histories dropped (checked by
  // disabling the carry-over) the top sphere slips by 2.6e-7 m before its springs rebuild.
  for (std::uint64_t id : {0u, 1u, 2u}) {
    const Vec3 a = with.bodies().x[with.bodies().index_of(id)], b = without.bodies().x[without.bodies().index_of(id)];
    CHECK(norm(a - b) < 1e-12);
  }
}

TEST_CASE("A particle that needs a smaller time step cannot be added mid-run", "[dem][insertion]") {
  Simulation sim = pyramid();
  CHECK_THROWS_AS(sim.add_sphere(0, 0.0003, {0.5, 0.5, 0.2}), InputError);
  CHECK_THROWS_WITH(sim.add_sphere(0, 0.0003, {0.5, 0.5, 0.2}), Catch::Matchers::Contains("smaller than the running"));
}

#include "barley_box_fixture.hpp"
#include "dem/pour.hpp"
#include "dem/walls/box.hpp"

namespace {

/// Spheres (6 mm, 1380 kg/m^3: 0.156 g each) poured into an open box 0.1 x 0.1 x 0.2 m.
struct PourBox {
  Simulation sim;
  Random rng{7};
  PourBox() : sim(materials(), fixed_step()) {
    sim.add_wall("box", std::make_shared<BoxGeometry>(Vec3{0, 0, 0}, Vec3{0.1, 0.1, 0.2}), 1);
  }
  static MaterialTable materials() { return testing::barley_perspex(); }
  static SimulationSettings fixed_step() {  // the box starts empty: no particle to take a step from
    SimulationSettings st;
    st.time_step = 1e-4;
    return st;
  }
  ParticleBatch batch(double mass, double region_height) const {
    ParticleBatch b;
    b.label = "test pour";
    b.material = 0;
    b.diameter = 0.006;
    b.mass = mass;
    b.region_min = {0, 0, 0.2 - region_height};
    b.region_max = {0.1, 0.1, 0.2};
    return b;
  }
};

}  // namespace

TEST_CASE("A pour delivers its mass at the requested rate", "[dem][insertion]") {
  PourBox box;
  Simulation& sim = box.sim;
  const double rate = 0.5, interval = 0.01;
  Pour pour(box.batch(0.05, 0.05), rate, 0.0, interval);
  const double one = 1380 * 4.0 / 3.0 * M_PI * 0.003 * 0.003 * 0.003;
  for (int s = 0; s < 1500; ++s) {
    pour.update(sim, box.rng);
    sim.step();
    if (s == 500) {  // t = 0.05 s: between rate * t and rate * (t + interval), within one particle
      CHECK(pour.poured_mass() >= rate * sim.time() - one);
      CHECK(pour.poured_mass() <= rate * (sim.time() + interval) + one);
    }
  }
  CHECK(pour.done());
  CHECK(std::abs(pour.poured_mass() - 0.05) <= one);
  CHECK(sim.bodies().size() == pour.poured_count());
}

TEST_CASE("A pour into a region that fills up waits for room and still delivers everything", "[dem][insertion]") {
  PourBox box;
  Simulation& sim = box.sim;
  Pour pour(box.batch(0.05, 0.012), 5.0, 0.0, 0.01);  // a thin region: about 100 spheres fit at once
  for (int s = 0; s < 6000 && !pour.done(); ++s) {
    pour.update(sim, box.rng);
    sim.step();
  }
  CHECK(pour.waits() > 0);
  CHECK(pour.done());
}
