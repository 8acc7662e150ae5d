// Walls under prescribed motion: particles must ride along with a moving container, through the
// wall's surface velocity in the contact forces, and start to slide at the friction angle.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <memory>
#include <numbers>

#include "dem/container_meshes.hpp"
#include "dem/motion/sinusoidal_motion.hpp"
#include "dem/motion/steady_motion.hpp"
#include "dem/motion/tabulated_motion.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/mesh.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::dem;
using Catch::Matchers::WithinAbs;

namespace {

MaterialTable grain_and_floor(double mu) {
  MaterialTable mt;
  mt.add({"grain", 1380, 2.6e7, 0.3});
  mt.add({"floor", 1190, 7.97e8, 0.38});
  mt.set_pair(0, 0, {0.5, mu, 0.0, true});
  mt.set_pair(0, 1, {0.5, mu, 0.0, true});
  return mt;
}

}  // namespace

/// A flat block of four spheres (it cannot roll), resting on z = 0 at (x, y).
std::uint64_t add_block(Simulation& sim, double x, double y, double r = 0.003) {
  Shape block;
  block.name = "block";
  for (double dx : {-r, r})
    for (double dy : {-r, r}) block.spheres.push_back({{dx, dy, 0}, r});
  return sim.add_clump(block, 0, 1380, {x, y, r * 0.999});
}

TEST_CASE("On a turning disc a block co-rotates; a free ball orbits at 2/7 of the disc's rate",
          "[dem][motion][walls]") {
  // 0.5 rad/s at r = 0.05 m needs a centripetal 0.0125 m/s^2, far below mu g: the block sticks.
  // A ball placed at rest instead picks up 2/7 of the surface speed and then rolls without slip,
  // its centre obeying dv/dt = (2/7) Omega x v: a circle about the disc centre at 2 Omega / 7
  // (Weltner 1979, Am. J. Phys. 47:984).
  const double rate = 0.5, r = 0.003;
  Simulation sim(grain_and_floor(0.5), SimulationSettings{});
  add_block(sim, 0.05, 0);
  sim.add_sphere(0, r, {0, 0.05, r * 0.999});
  sim.add_wall("disc", std::make_shared<MeshGeometry>(tray_mesh(0.1, 0.0, 64)), 1);
  sim.walls().back().set_motion({std::make_shared<SteadyMotion>(Vec3{}, Vec3{0, 0, rate}), {0, 0, 0}});
  sim.setup();
  sim.run_steps(static_cast<std::uint64_t>(2.0 / sim.dt()));  // 2 s: one radian of the disc
  const Vec3 xb = sim.bodies().x[sim.bodies().index_of(0)], vb = sim.bodies().v[sim.bodies().index_of(0)];
  CHECK_THAT(std::atan2(xb.y, xb.x), WithinAbs(rate * sim.time(), 0.01));  // turned with the disc
  CHECK_THAT(std::hypot(xb.x, xb.y), WithinAbs(0.05, 1e-4));
  CHECK(norm(vb - cross(Vec3{0, 0, rate}, xb)) < 0.01 * rate * 0.05);
  const Vec3 xs = sim.bodies().x[sim.bodies().index_of(1)];
  CHECK_THAT(std::atan2(xs.y, xs.x) - std::numbers::pi / 2, WithinAbs(2.0 / 7.0 * rate * sim.time(), 0.01));
  CHECK_THAT(std::hypot(xs.x, xs.y), WithinAbs(0.05, 5e-4));
}

TEST_CASE("In a surging box a block moves with the box; a ball lags by 5/7 of the box's motion",
          "[dem][motion][walls]") {
  // Surge of 50 mm at 0.5 Hz: peak acceleration 0.49 m/s^2 < mu g, so the block rides along. A
  // rolling ball accelerates at 2/7 of the floor's acceleration (Newton + rolling constraint), so
  // relative to the box it moves by -5/7 of the box's displacement.
  const double r = 0.003, amplitude = 0.05;
  Simulation sim(grain_and_floor(0.5), SimulationSettings{});
  add_block(sim, 0.1, 0.03);
  sim.add_sphere(0, r, {0.1, 0.07, r * 0.999});
  sim.add_wall("box", std::make_shared<MeshGeometry>(box_mesh({0, 0, 0}, {0.2, 0.1, 0.1}, {1, 1, 1, 1, 1, 0})), 1);
  std::array<SinusoidalMotion::Dof, 6> d{};
  d[3] = {amplitude, 0.5, std::numbers::pi / 2};  // starts at rest: x = A cos(omega t)
  sim.walls().back().set_motion({std::make_shared<SinusoidalMotion>(d), {0, 0, 0}});
  sim.setup();
  const Vec3 block0 = sim.bodies().x[sim.bodies().index_of(0)], ball0 = sim.bodies().x[sim.bodies().index_of(1)], shift0 = sim.walls()[0].pose().origin;
  double block_worst = 0, ball_worst = 0, box_max = 0;
  for (int s = 0; s < static_cast<int>(3.0 / sim.dt()); ++s) {
    sim.step();
    const Vec3 shift = sim.walls()[0].pose().origin - shift0;
    box_max = std::max(box_max, std::abs(shift.x));
    block_worst = std::max(block_worst, norm(sim.bodies().x[sim.bodies().index_of(0)] - block0 - shift));
    ball_worst = std::max(ball_worst, norm(sim.bodies().x[sim.bodies().index_of(1)] - ball0 - (2.0 / 7.0) * shift));
  }
  CHECK_THAT(box_max, WithinAbs(2 * amplitude, 1e-4));  // the box did move
  CHECK(block_worst < 2e-4);                        // the block stayed put in it
  CHECK(ball_worst < 0.02 * amplitude);             // the ball followed 2/7 of it
}

TEST_CASE("Tilt table: a clump on a slowly tilting floor starts to slide within 0.5 degrees of atan(mu)",
          "[dem][motion][walls]") {
  const double mu = GENERATE(0.3, 0.45);
  const double onset = std::atan(mu) * 180 / std::numbers::pi;
  // A flat block of four spheres, resting on a tilting square floor; the tilt ramps at 1 deg/s
  // from 4 degrees below the friction angle (a recorded motion of two rows: linear in time).
  const grainscale::testing::TempDir tmp;  // a fresh folder: a parallel ctest cannot race on the file
  const std::string csv = tmp / "tilt.csv";
  {
    std::ofstream f(csv);
    f << "t_s,roll_deg,pitch_deg,yaw_deg,surge_m,sway_m,heave_m\n0,0," << onset - 4 << ",0,0,0,0\n10,0," << onset + 6
      << ",0,0,0,0\n";
  }
  SimulationSettings st;
  st.rolling.model = RollingModel::none;
  Simulation sim(grain_and_floor(mu), st);
  Shape block;
  block.name = "block";
  const double r = 0.003;
  for (double x : {-r, r})
    for (double y : {-r, r}) block.spheres.push_back({{x, y, 0}, r});
  // Place it on the floor already tilted to the start angle (pitch about y through the origin).
  const Quat tilt0 = axis_angle({0, 1, 0}, (onset - 4) * std::numbers::pi / 180);
  sim.add_clump(block, 0, 1380, rotate(tilt0, Vec3{0, 0, r * 0.999}), tilt0);
  TriangleMesh floor;
  floor.add_quad({-0.05, -0.05, 0}, {0.05, -0.05, 0}, {0.05, 0.05, 0}, {-0.05, 0.05, 0});
  sim.add_wall("floor", std::make_shared<MeshGeometry>(floor), 1);
  sim.walls().back().set_motion({std::make_shared<TabulatedMotion>(TabulatedMotion::load(csv)), {0, 0, 0}});
  sim.setup();
  // Sliding: the block's position in the floor's frame has moved by more than 0.2 mm downhill.
  Vec3 start_in_floor{};
  double slide_angle = -1;
  for (int s = 0; s < static_cast<int>(10.0 / sim.dt()); ++s) {
    sim.step();
    const Vec3 in_floor = sim.walls()[0].pose().to_body(sim.bodies().x[sim.bodies().index_of(0)]);
    if (s == static_cast<int>(0.5 / sim.dt())) start_in_floor = in_floor;  // after settling on it
    if (s > static_cast<int>(0.5 / sim.dt()) && norm(in_floor - start_in_floor) > 2e-4) {
      slide_angle = onset - 4 + sim.time();
      break;
    }
  }
  INFO("mu = " << mu << ": friction angle " << onset << " deg, slid at " << slide_angle << " deg");
  CHECK_THAT(slide_angle, WithinAbs(onset, 0.5));
}

TEST_CASE("A rocking box finds every wall contact, though it asks only the spheres within reach of it",
          "[dem][motion][walls]") {
  // ForceField asks a wall about a sphere only if the sphere was within reach of it, in the wall's
  // frame, when the masks were made, and makes them again once the wall has moved half a skin in
  // the spheres' region. A rocking box (+-20 deg at 2 Hz about a pivot 0.2 m away, so its floor
  // sweeps ~0.07 m) with a loose bed that slides to and fro in it: at every step the contacts found
  // must be exactly those a search over every sphere and wall finds.
  const double r = 0.003;
  Simulation sim(grain_and_floor(0.3), SimulationSettings{});
  for (int ix = 0; ix < 12; ++ix)
    for (int iy = 0; iy < 4; ++iy)
      for (int iz = 0; iz < 3; ++iz) {
        sim.add_sphere(0, r, {0.01 + 0.0075 * ix, 0.008 + 0.0075 * iy, 0.004 + 0.0065 * iz});
      }
  sim.add_wall("box", std::make_shared<MeshGeometry>(box_mesh({0, 0, 0}, {0.1, 0.04, 0.06}, {1, 1, 1, 1, 1, 0})), 1);
  std::array<SinusoidalMotion::Dof, 6> d{};
  d[0] = {20 * std::numbers::pi / 180, 2.0, 0};  // roll about x
  sim.walls().back().set_motion({std::make_shared<SinusoidalMotion>(d), {0.05, 0.02, -0.2}});
  sim.setup();
  std::size_t worst_miss = 0, most = 0, builds_seen = sim.neighbors().builds();
  const int steps = static_cast<int>(0.5 / sim.dt());
  for (int s = 0; s < steps; ++s) {
    sim.step();
    std::size_t expected = 0;
    const Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      WallContact wc[ForceField::kWallSlots + 1];
      expected += static_cast<std::size_t>(sim.walls()[0].contacts(p.x[i], p.radius[i], wc, ForceField::kWallSlots + 1));
    }
    const std::size_t found = sim.diagnostics().wall_contacts;
    worst_miss = std::max(worst_miss, expected > found ? expected - found : found - expected);
    most = std::max(most, expected);
  }
  INFO(steps << " steps, " << sim.neighbors().builds() - builds_seen << " list builds, up to " << most
              << " wall contacts");
  CHECK(worst_miss == 0);
  CHECK(most > 40);  // the bed lay on the floor and slid into the side walls
}
