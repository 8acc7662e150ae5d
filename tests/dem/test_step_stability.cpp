// The per-body step-stability check (dem/step_stability.hpp) against the exact two-body result.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dem/rigid_rotation.hpp"
#include "impact_fixture.hpp"

using namespace grainscale::dem;
using namespace grainscale::dem::testing;
using Catch::Matchers::WithinRel;

TEST_CASE("Two equal spheres pressed together: the margin is the damped leapfrog limit of their contact",
          "[dem][stability]") {
  // One Hertz contact between equal spheres is an oscillator with Omega^2 = S_n / m*, m* = m / 2, and
  // damping ratio zeta = sqrt(5/6) |beta| (the EDEM damping); leapfrog is stable for
  // Omega dt < 2 (sqrt(1 + zeta^2) - zeta) (Belytschko et al. 2000). Both stages of the check are
  // exact here: the bound for small margins, the 6-dof mode above kRefineAbove.
  const double e = GENERATE(0.1, 0.5, 0.9);
  const double dt = GENERATE(2e-7, 1e-6, 3e-6);
  const Solid ball{5e6, 0.3, 1000};
  SimulationSettings st = impact_settings();
  st.time_step = dt;
  Simulation sim(impact_materials(ball, ball, e, 0.5), st);
  const double r = 0.002, overlap = 1e-4;
  sim.add_sphere(0, r, {0, 0, 0});
  sim.add_sphere(0, r, {2 * r - overlap, 0, 0});
  sim.setup();
  const StepStability s = sim.check_stability();

  const Material& m = sim.materials()[0];
  const double e_star = 1 / (2 * (1 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus());
  const double s_n = 2 * e_star * std::sqrt(0.5 * r * overlap);
  const double mass = m.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double omega = std::sqrt(s_n / (0.5 * mass));
  const double beta = std::log(e) / std::sqrt(std::log(e) * std::log(e) + std::numbers::pi * std::numbers::pi);
  const double zeta = std::sqrt(5.0 / 6.0) * -beta;
  const double margin = omega * dt / (2 * (std::sqrt(1 + zeta * zeta) - zeta));
  INFO("e = " << e << ", dt = " << dt << ": margin " << s.margin << " expected " << margin);
  CHECK_THAT(s.margin, WithinRel(margin, 1e-9));
  CHECK_THAT(s.zeta, WithinRel(zeta, 1e-9));
  CHECK(s.contacts == 1);
  CHECK(s.refined == (margin > StepStabilityMonitor::kRefineAbove));
}

TEST_CASE("A sphere on a wall: Omega^2 = S_n / m, and without contacts no margin", "[dem][stability]") {
  const Solid ball{5e6, 0.3, 1000};
  SimulationSettings st = impact_settings();
  st.time_step = 1e-6;
  Simulation sim(impact_materials(ball, ball, 0.5, 0.5), st);
  const double r = 0.002, overlap = 5e-5;
  sim.add_sphere(0, r, {0, 0, r - overlap});
  sim.add_sphere(0, r, {0.1, 0, 0.5});  // far from everything
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 2);
  sim.setup();
  const StepStability s = sim.check_stability();
  const Material& m = sim.materials()[0];
  const double e_star = 1 / ((1 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus());  // rigid wall
  const double omega = std::sqrt(2 * e_star * std::sqrt(r * overlap) / (m.density * 4.0 / 3.0 * std::numbers::pi * r * r * r));
  CHECK_THAT(s.omega_dt, WithinRel(omega * 1e-6, 1e-9));
  CHECK(s.body == 0);

  Simulation empty(impact_materials(ball, ball, 0.5, 0.5), st);
  empty.add_sphere(0, r, {0, 0, 1});
  empty.setup();
  CHECK(empty.check_stability().body == -1);
  CHECK(empty.check_stability().margin == 0);
}

TEST_CASE("A tilted three-sphere clump on a wall at one sphere: Omega^2 = S_n (1/m + (r x n)^T I^-1 (r x n))",
          "[dem][stability][clump]") {
  // One contact on an anisotropic body: the bound is exact (Gershgorin on a 1x1 block), and so is
  // the refined mode. The body's compliance at the contact point is computed here the long way, by
  // turning the lever's moment arm into the principal frame.
  const Solid ball{5e6, 0.3, 1000};
  SimulationSettings st = impact_settings();
  st.time_step = GENERATE(1e-6, 2e-5);  // margin below and above StepStabilityMonitor::kRefineAbove
  const double r = 0.002, overlap = 5e-5;
  Shape ell;
  ell.spheres = {{{0, 0, 0}, r}, {{1.5 * r, 0, 0}, r}, {{0, 1.2 * r, 0}, r}};
  const Quat tilt = axis_angle((1 / std::sqrt(14.0)) * Vec3{1, 2, 3}, 0.7);
  // Where the clump's lowest sphere lies below its centre of mass, from a first placement.
  double drop = 0;
  {
    Simulation probe(impact_materials(ball, ball, 0.5, 0.5), st);
    probe.add_clump(ell, 0, 1000, {0, 0, 1}, tilt);
    probe.setup();
    double lowest = 1, second = 1;
    for (const Vec3& x : probe.particles().x) {
      if (x.z < lowest) second = lowest, lowest = x.z;
      else second = std::min(second, x.z);
    }
    REQUIRE(second - lowest > 2 * overlap);  // one sphere touches
    drop = 1 - lowest;
  }
  Simulation sim(impact_materials(ball, ball, 0.5, 0.5), st);
  sim.add_clump(ell, 0, 1000, {0, 0, drop + r - overlap}, tilt);
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 2);
  sim.setup();
  const StepStability s = sim.check_stability();
  REQUIRE(s.contacts == 1);

  const Bodies& b = sim.bodies();
  const Particles& p = sim.particles();
  std::size_t low = 0;
  for (std::size_t i = 1; i < p.size(); ++i) low = p.x[i].z < p.x[low].z ? i : low;
  const Vec3 n{0, 0, 1};
  const Vec3 lever = p.x[low] - (r - overlap) * n - b.x[0];
  const Vec3 arm = to_body(b.q[0], cross(lever, n));
  const Vec3& I = b.inertia[0];
  const double compliance = 1 / b.mass[0] + arm.x * arm.x / I.x + arm.y * arm.y / I.y + arm.z * arm.z / I.z;
  const Material& m = sim.materials()[0];
  const double e_star = 1 / ((1 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus());  // rigid wall
  const double omega = std::sqrt(2 * e_star * std::sqrt(r * overlap) * compliance);
  INFO("dt = " << st.time_step << ": Omega dt " << s.omega_dt << " expected " << omega * st.time_step);
  CHECK(I.x != I.y);  // an anisotropic body
  CHECK_THAT(s.omega_dt, WithinRel(omega * st.time_step, 1e-9));
  CHECK(s.refined == (s.margin > StepStabilityMonitor::kRefineAbove));
}
