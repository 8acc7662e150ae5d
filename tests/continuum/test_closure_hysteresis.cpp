// Start/stop hysteresis of the flow closure (continuum/closure/bed_friction.hpp, (F3)): a bed at rest
// starts above θ_start = φ + Δθ, a moving one stops at θ_stop = φ (Pouliquen 1999; Daerr & Douady
// 1999). Checked against the two states' analytic motion and the stick-slip of slow tilting (the
// surface angle saws between the two thresholds, as in a slowly rotated drum: Jaeger, Liu & Nagel,
// Phys. Rev. Lett. 62, 1989).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "closure_fixture.hpp"
#include "dem/motion/platform_tilt.hpp"
#include "dem/yaml_map.hpp"
#include <yaml-cpp/yaml.h>

using namespace grainscale::continuum::closure;
using namespace closure_test;

namespace {

/// Held at tilt θ₁ until t₁, then at θ₂ (about +y, the +x end down).
class StepTilt final : public grainscale::dem::MotionProfile {
 public:
  StepTilt(double theta1, double t1, double theta2) : theta1_(theta1), t1_(t1), theta2_(theta2) {}
  grainscale::dem::RigidMotionState at(double t) const override {
    grainscale::dem::RigidMotionState s;
    s.rotation = grainscale::dem::axis_angle({0, 1, 0}, t < t1_ ? theta1_ : theta2_);
    return s;
  }
  double period() const override { return 0; }
  std::string describe() const override { return "step tilt"; }

 private:
  double theta1_, t1_, theta2_;
};

ContainerGravity step_tilted(double theta1, double t1, double theta2) {
  ContainerPlacement p;
  p.gravity = 9.81;
  return ContainerGravity(std::make_shared<StepTilt>(theta1, t1, theta2), p);
}

}  // namespace

TEST_CASE("hysteresis: between theta_stop and theta_start a bed at rest stays, a moving one keeps moving",
          "[closure][hysteresis]") {
  // A deep bed (h = 2 m ≫ ℓ = 2 cm) with its surface parallel to a floor tilted by θ₂ = 30°, between
  // θ_stop = φ = 26.7° and θ_start = 26.7° + 5°. Started from rest it stays exactly at rest. Tilted
  // first to θ₁ = 34° for 0.2 s it starts at once and, back at θ₂, goes on accelerating: far from
  // the walls a uniform layer has du/dt = g (sin θ − cos θ tan φ) (Δμ = 0: Coulomb), so
  //   u(t) = g (sin θ₁ − cos θ₁ tan φ) t₁ + g (sin θ₂ − cos θ₂ tan φ) (t − t₁).
  const double phi = 26.7, excess = 5, theta1 = 34 * kDeg, t1 = 0.2, theta2 = 30 * kDeg, t_end = 0.5;
  SectionSettings s = section(40, 200, phi, 14, 0.02);
  s.friction.start_excess_deg = excess;
  s.max_dt = 1e-3;  // resolves the switch at t₁
  const std::vector<double> h(s.nx, 2.0);
  {
    ShallowGranularFlow rest(s, tilted(theta2), h);
    rest.advance(t_end);
    CHECK(rest.depth() == h);  // bit for bit
    for (double u : rest.surface_speed()) CHECK(u == 0.0);
  }
  {
    ShallowGranularFlow moving(s, step_tilted(theta1, t1, theta2), h);
    moving.advance(t_end);
    const double g = 9.81, mu = std::tan(phi * kDeg);
    const double expected = g * (std::sin(theta1) - std::cos(theta1) * mu) * t1 +
                            g * (std::sin(theta2) - std::cos(theta2) * mu) * (t_end - t1);
    CHECK(moving.surface_speed()[s.nx / 2] == Approx(expected).epsilon(1e-3));
  }
  // Without the excess the bed at θ₂ is above its one threshold and starts from rest.
  s.friction.start_excess_deg = 0;
  ShallowGranularFlow plain(s, tilted(theta2), h);
  plain.advance(t_end);
  CHECK(plain.surface_speed()[s.nx / 2] > 0.3);
}

TEST_CASE("hysteresis: a slowly tilted bed starts at theta_start and comes to rest at theta_stop",
          "[closure][hysteresis]") {
  // A deep bed tilted over 60 s (quasi-statically) and held, as "slow tilting leaves a deep bed's
  // surface at the internal friction angle" (test_closure_flow.cpp). Held at 35°, past θ_start =
  // φ + Δθ: it does not move until the tilt reaches θ_start, then flows until its surface stands at
  // θ_stop = φ (overshooting by the avalanche's inertia at most 1°). Held at θ_start − 0.5°, above φ:
  // it never moves, and its surface stays at the tilt.
  const double phi = 26.7, excess = GENERATE(3.0, 6.0);
  const bool past = GENERATE(true, false);
  const double hold = past ? 35.0 : phi + excess - 0.5;
  SectionSettings s = section(4, 80, phi, 14, 0.02);
  s.friction.delta_mu = 0.26;
  s.friction.grain_diameter = 2e-3;
  s.friction.start_excess_deg = excess;
  grainscale::dem::PlatformTilt::Params p;
  p.amplitude = hold * kDeg;
  p.frequency = 1.0 / 120;  // ramp over 60 s
  p.pause = 1e4;
  ContainerPlacement place;
  ShallowGranularFlow flow(s, ContainerGravity(std::make_shared<grainscale::dem::PlatformTilt>(p), place),
                           std::vector<double>(s.nx, 1.5));
  double start_tilt = NAN;
  flow.advance(150.0, [&](const ShallowGranularFlow& f) {
    if (std::isnan(start_tilt) && std::any_of(f.surface_speed().begin(), f.surface_speed().end(), [](double u) { return u != 0; })) {
      start_tilt = f.gravity().tilt(f.gravity().state(f.time())) / kDeg;
    }
  });
  double lo = 90, hi = 0;  // the surface angle per face in the middle
  for (int f = 20; f <= 60; ++f) {
    const double angle = hold - std::atan((flow.depth()[f] - flow.depth()[f - 1]) / flow.dx()) / kDeg;
    lo = std::min(lo, angle), hi = std::max(hi, angle);
  }
  CAPTURE(excess, hold, start_tilt, lo, hi);
  for (double u : flow.surface_speed()) CHECK(std::abs(u) < 1e-3);  // the tail of the avalanche creeps (μ(I) near μ_s)
  if (past) {
    CHECK(start_tilt == Approx(phi + excess).margin(0.1));  // the tilt moves 0.05° in a step
    CHECK(hi < phi + 0.3);
    CHECK(lo > phi - 1.0);
  } else {
    CHECK(std::isnan(start_tilt));
    CHECK(lo == Approx(hold).margin(1e-9));
    CHECK(hi == Approx(hold).margin(1e-9));
  }
}

TEST_CASE("hysteresis: the start excess is read from YAML with its range", "[closure][hysteresis][input]") {
  using grainscale::InputError;
  auto read = [](const std::string& text) {
    return bed_friction_from_yaml(grainscale::YamlMap(YAML::Load(text), "material.yaml", "material"));
  };
  CHECK(read("{internal_friction_deg: 28}").start_excess_deg == 0.0);
  CHECK(read("{internal_friction_deg: 28, start_excess_deg: 4.5}").start_excess_deg == 4.5);
  CHECK_THROWS_AS(read("{start_excess_deg: -1}"), InputError);
  CHECK_THROWS_AS(read("{start_excess_deg: 31}"), InputError);
  CHECK_THROWS_WITH(read("{internal_friction_deg: 80, start_excess_deg: 20}"),
                    Catch::Contains("start_excess_deg") && Catch::Contains("89"));
}
