// A sphere on a plane under gravity: the transition from sliding to rolling, and rolling resistance.
// References (rigid-body mechanics of a solid sphere, I = 2/5 m r^2):
//   * launched without spin it slides until v = 5/7 v0, then rolls;
//   * a rolling resistance torque mu_r F_n r decelerates it at (5/7) mu_r g, so it stops after
//     s = 7 v0^2 / (10 mu_r g);
//   * on an incline it stays put if tan(theta) < mu_r, else accelerates at (5/7) g (sin - mu_r cos).
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "dem/simulation.hpp"
#include "dem/walls/plane.hpp"

using namespace grainscale::dem;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

constexpr double kG = 9.81;
constexpr double kR = 0.005;

struct Setup {
  RollingModel model = RollingModel::constant_torque;
  double mu = 0.5, mu_r = 0.1, incline = 0;  // incline in radians (gravity tilted towards +x)
  Vec3 v0, w0;
};

/// A sphere resting on the plane z = 0 at its static overlap, with the given initial motion.
Simulation make(const Setup& s) {
  MaterialTable mt;
  const int ball = mt.add({"ball", 1380, 2.6e7, 0.3});
  const int floor = mt.add({"floor", 1190, 7.97e8, 0.38});
  mt.set_pair(ball, floor, {0.5, s.mu, s.mu_r, true});
  mt.set_pair(ball, ball, {0.5, s.mu, s.mu_r, true});
  SimulationSettings st;
  st.gravity = {kG * std::sin(s.incline), 0, -kG * std::cos(s.incline)};
  st.rolling.model = s.model;
  st.time_step_fraction = 0.1;
  Simulation sim(mt, st);
  // Static Hertz overlap under the normal weight, so the run starts without a bounce.
  const Material& a = mt[ball];
  const Material& b = mt[floor];
  const double e_eff = 1 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus() +
                            (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus());
  const double m = a.density * 4.0 / 3.0 * M_PI * kR * kR * kR;
  const double delta = std::pow(3 * m * kG * std::cos(s.incline) / (4 * e_eff * std::sqrt(kR)), 2.0 / 3.0);
  sim.add_sphere(ball, kR, {0, 0, kR - delta}, s.v0, s.w0);
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), floor);
  sim.setup();
  return sim;
}

void run_for(Simulation& sim, double seconds) {
  const auto n = static_cast<std::uint64_t>(seconds / sim.dt());
  sim.run_steps(n);
}

}  // namespace

TEST_CASE("A sphere launched without spin starts rolling at 5/7 of its launch speed", "[dem][rolling]") {
  const double v0 = 1.0;
  Simulation sim = make({RollingModel::none, 0.5, 0.0, 0.0, {v0, 0, 0}, {}});
  run_for(sim, 3 * 2 * v0 / (7 * 0.5 * kG));  // three times the sliding time 2 v0 / (7 mu g)
  const Particles& p = sim.particles();
  CHECK_THAT(p.v[0].x, WithinRel(5.0 / 7.0 * v0, 0.01));
  CHECK_THAT(p.omega[0].y * kR, WithinRel(5.0 / 7.0 * v0, 0.01));  // rolling: omega r = v
}

TEST_CASE("Rolling resistance stops a rolling sphere at the analytic distance", "[dem][rolling]") {
  const RollingModel model = GENERATE(RollingModel::constant_torque, RollingModel::epsd);
  const double mu_r = GENERATE(0.05, 0.1);
  const double v0 = 0.5;
  Simulation sim = make({model, 0.5, mu_r, 0.0, {v0, 0, 0}, {0, v0 / kR, 0}});
  const double stop_time = v0 / (5.0 / 7.0 * mu_r * kG);
  run_for(sim, 1.3 * stop_time);
  const Particles& p = sim.particles();
  INFO("model " << static_cast<int>(model) << ", mu_r = " << mu_r);
  CHECK_THAT(p.x[0].x, WithinRel(7 * v0 * v0 / (10 * mu_r * kG), 0.02));
  CHECK(std::abs(p.v[0].x) < 1e-3 * v0);  // and stays stopped (no chatter)
}

TEST_CASE("On an incline a sphere with rolling resistance holds below tan(theta) = mu_r and rolls above",
          "[dem][rolling]") {
  const RollingModel model = GENERATE(RollingModel::constant_torque, RollingModel::epsd);
  const double mu_r = 0.1;
  INFO("model " << static_cast<int>(model));
  SECTION("holds at tan(theta) = mu_r / 2") {
    Simulation sim = make({model, 0.5, mu_r, std::atan(0.5 * mu_r), {}, {}});
    run_for(sim, 0.5);
    CHECK(std::abs(sim.particles().x[0].x) < 0.01 * kR);
  }
  SECTION("rolls at tan(theta) = 2 mu_r with acceleration (5/7) g (sin - mu_r cos)") {
    const double th = std::atan(2 * mu_r);
    Simulation sim = make({model, 0.5, mu_r, th, {}, {}});
    const double t = 0.3;
    run_for(sim, t);
    const double a = 5.0 / 7.0 * kG * (std::sin(th) - mu_r * std::cos(th));
    CHECK_THAT(sim.particles().v[0].x, WithinRel(a * t, 0.02));
  }
}
