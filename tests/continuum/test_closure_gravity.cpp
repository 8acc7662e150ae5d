// Container-frame gravity (continuum/closure/container_gravity.hpp, (G1)) against closed forms.
#include <catch2/catch.hpp>
#include <cmath>

#include "closure_fixture.hpp"
#include "dem/motion/platform_tilt.hpp"
#include "dem/motion/steady_motion.hpp"

using namespace grainscale;
using namespace grainscale::continuum::closure;
using closure_test::kDeg;

TEST_CASE("closure gravity: tilt about a pivot under the floor, turning steadily", "[closure][gravity]") {
  // ω about +y through a pivot R below the floor point: g_t = g sin ωt, g_n = g cos ωt − ω² R.
  const double omega = 0.3, R = 10, g = 9.81;
  ContainerPlacement p;
  p.pivot = {0, 0, -R};
  p.gravity = g;
  ContainerGravity grav(std::make_shared<dem::SteadyMotion>(dem::Vec3{0, 0, 0}, dem::Vec3{0, omega, 0}), p);
  for (double t : {0.0, 0.7, 1.9}) {
    double gt = 0, gn = 0;
    const auto s = grav.state(t);
    grav.components(s, 0.0, gt, gn);
    CHECK(gt == Approx(g * std::sin(omega * t)).margin(1e-12));
    CHECK(gn == Approx(g * std::cos(omega * t) - omega * omega * R).margin(1e-12));
    CHECK(grav.tilt(s) == Approx(omega * t).margin(1e-12));
  }
}

TEST_CASE("closure gravity: angular acceleration of a container off the axis drives the grain", "[closure][gravity]") {
  // Platform tilt at the start of a transition (θ = A, θ' = 0, θ'' = −A (π/h)²): a point at
  // height H above the axis (axis at the floor's level below x = 0... pivot at (0, 0, −H)) feels
  // −α × r: along x, −(α ŷ × H ẑ)·x̂ = −α H, so g_t = g sin A − α H (in the rotated frame).
  dem::PlatformTilt::Params pp;
  pp.amplitude = 20 * kDeg;
  pp.frequency = 0.1;
  pp.pause = 4;
  pp.start_level = false;
  auto motion = std::make_shared<dem::PlatformTilt>(pp);
  const double H = 5;
  ContainerPlacement p;
  p.pivot = {0, 0, -H};
  ContainerGravity grav(motion, p);
  const double t = 4.0 + 1e-9;  // just after the hold, the transition begins
  double theta = 0, rate = 0, accel = 0;
  motion->angle(t, theta, rate, accel);
  double gt = 0, gn = 0;
  grav.components(grav.state(t), 0.0, gt, gn);
  CHECK(gt == Approx(9.81 * std::sin(theta) - accel * H).epsilon(1e-6));
  CHECK(gn == Approx(9.81 * std::cos(theta)).epsilon(1e-6));
}
