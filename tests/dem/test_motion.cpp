// Motion profiles (dem/motion/): the angular velocity and acceleration they report must be the
// derivatives of the rotation they report, and the report's platform cycle must be as specified.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include "dem/input_error.hpp"
#include "dem/motion/platform_tilt.hpp"
#include "dem/motion/sinusoidal_motion.hpp"
#include "dem/motion/steady_motion.hpp"
#include "dem/motion/tabulated_motion.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::dem;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::Contains;

namespace {

constexpr double kDeg = std::numbers::pi / 180;

std::shared_ptr<MotionProfile> platform() {
  PlatformTilt::Params p;
  p.amplitude = 24 * kDeg;
  p.axis = {0.2, 1, 0.1};  // deliberately not a coordinate axis
  return std::make_shared<PlatformTilt>(p);
}

std::shared_ptr<MotionProfile> ship() {
  std::array<SinusoidalMotion::Dof, 6> d{};
  d[0] = {20 * kDeg, 1.0 / 12, 0.3};   // roll
  d[1] = {5 * kDeg, 1.0 / 7, 1.1};     // pitch
  d[2] = {2 * kDeg, 1.0 / 30, -0.4};   // yaw
  d[3] = {0.5, 1.0 / 9, 0.0};          // surge
  d[4] = {0.3, 1.0 / 11, 0.7};         // sway
  d[5] = {1.5, 1.0 / 8, 2.0};          // heave
  return std::make_shared<SinusoidalMotion>(d);
}

std::string write_file(const grainscale::testing::TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = dir / name;
  grainscale::testing::write_text(path, text);
  return path;
}

/// A record sampled from ship() every 0.05 s over 60 s.
std::shared_ptr<MotionProfile> recorded_ship() {
  // load() reads the whole record, so the file need not outlive this call; a fresh folder each
  // time keeps parallel ctest processes from racing on it.
  const grainscale::testing::TempDir tmp;
  const std::string path = [&] {
    const auto s = ship();
    std::string csv = "# sampled from a sinusoidal ship motion\nt_s,roll_deg,pitch_deg,yaw_deg,surge_m,sway_m,heave_m\n";
    for (int k = 0; k <= 1200; ++k) {
      const double t = 0.05 * k;
      // Recover the angles from the known sinusoids rather than from the quaternion.
      const double w = 2 * std::numbers::pi;
      char line[256];
      std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", t,
                    20 * std::sin(w / 12 * t + 0.3), 5 * std::sin(w / 7 * t + 1.1), 2 * std::sin(w / 30 * t - 0.4),
                    0.5 * std::sin(w / 9 * t), 0.3 * std::sin(w / 11 * t + 0.7), 1.5 * std::sin(w / 8 * t + 2.0));
      csv += line;
    }
    return write_file(tmp, "ship.csv", csv);
  }();
  return std::make_shared<TabulatedMotion>(TabulatedMotion::load(path));
}

}  // namespace

TEST_CASE("Angular velocity and acceleration are the derivatives of the rotation", "[dem][motion]") {
  // d/dt (R v) = omega x (R v) for any vector v, d omega/dt = alpha, d'(t) = velocity, d'' = acceleration;
  // checked by central differences (error O(h^2)).
  auto [name, profile] = GENERATE(table<const char*, std::shared_ptr<MotionProfile>>(
      {{"platform", platform()},
       {"sinusoids", ship()},
       {"record", recorded_ship()},
       {"steady", std::make_shared<SteadyMotion>(Vec3{0.01, 0, 0.02}, Vec3{0.1, -0.2, 0.3})}}));
  const double h = 1e-4;
  for (double t : {1.3, 6.1, 7.9, 14.2, 16.6, 23.5, 40.7}) {
    const RigidMotionState s = profile->at(t), a = profile->at(t + h), b = profile->at(t - h);
    for (const Vec3 v : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0.3, -0.5, 0.8}}) {
      const Vec3 fd = (1 / (2 * h)) * (rotate(a.rotation, v) - rotate(b.rotation, v));
      const Vec3 exact = cross(s.angular_velocity, rotate(s.rotation, v));
      INFO(name << " t = " << t);
      CHECK(norm(fd - exact) < 1e-6);
    }
    INFO(name << " t = " << t);
    CHECK(norm((1 / (2 * h)) * (a.angular_velocity - b.angular_velocity) - s.angular_acceleration) < 1e-5);
    CHECK(norm((1 / (2 * h)) * (a.displacement - b.displacement) - s.velocity) < 1e-6);
    CHECK(norm((1 / (2 * h)) * (a.velocity - b.velocity) - s.acceleration) < 1e-5);
  }
}

TEST_CASE("The report's platform: 18 s cycle, 4 s holds at +/-24 degrees, 5 s sinusoidal transitions",
          "[dem][motion]") {
  PlatformTilt::Params p;
  p.amplitude = 24 * kDeg;
  const PlatformTilt tilt(p);
  CHECK(tilt.period() == 18.0);
  // Sample the angle finely over two cycles and measure holds, extremes and transitions.
  double hold_plus = 0, hold_minus = 0, max_angle = -1, min_angle = 1;
  const double dt = 1e-3;
  double theta, rate, accel;
  tilt.angle(0, theta, rate, accel);
  CHECK_THAT(theta, WithinAbs(0, 1e-12));  // starts level
  CHECK_THAT(rate, WithinAbs(0, 1e-12));   // and at rest
  tilt.angle(5.0, theta, rate, accel);     // risen to +A after one transition
  CHECK_THAT(theta, WithinAbs(p.amplitude, 1e-12));
  for (int i = 0; i < 36000; ++i) {
    const double t = 5 + i * dt;
    tilt.angle(t, theta, rate, accel);
    if (std::abs(theta - p.amplitude) < 1e-12) hold_plus += dt;
    if (std::abs(theta + p.amplitude) < 1e-12) hold_minus += dt;
    max_angle = std::max(max_angle, theta);
    min_angle = std::min(min_angle, theta);
    // The transition is half a 0.1 Hz cosine: peak rate A pi f / (1/2) = A pi / 5 s.
    CHECK(std::abs(rate) <= p.amplitude * std::numbers::pi / 5 + 1e-12);
  }
  CHECK_THAT(hold_plus, WithinAbs(8.0, 2.5 * dt));  // two cycles, 4 s each
  CHECK_THAT(hold_minus, WithinAbs(8.0, 2.5 * dt));
  CHECK_THAT(max_angle, WithinAbs(24 * kDeg, 1e-12));
  CHECK_THAT(min_angle, WithinAbs(-24 * kDeg, 1e-12));
  // Phase runs 0 -> 1 over one period.
  CHECK_THAT(tilt.at(9.5).phase - tilt.at(5.0).phase, WithinAbs(0.25, 1e-12));
}

TEST_CASE("A recorded motion is interpolated smoothly: a finely sampled sinusoid is reproduced", "[dem][motion]") {
  const auto exact = ship(), record = recorded_ship();
  double worst_angle = 0, worst_rate = 0;
  for (double t = 1.0; t < 59; t += 0.0137) {  // between samples
    const RigidMotionState a = exact->at(t), b = record->at(t);
    const Quat d = a.rotation * conjugate(b.rotation);
    worst_angle = std::max(worst_angle, 2 * std::asin(std::min(1.0, std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z))));
    worst_rate = std::max(worst_rate, norm(a.angular_velocity - b.angular_velocity));
  }
  CHECK(worst_angle < 1e-6);  // rad; cubic splines at 0.05 s on periods >= 7 s
  CHECK(worst_rate < 1e-5);
}

TEST_CASE("Bad motion records name the file, the line and the column", "[dem][motion][input]") {
  const std::string header = "t_s,roll_deg,pitch_deg,yaw_deg,surge_m,sway_m,heave_m\n";
  const grainscale::testing::TempDir tmp;
  auto fails_with = [&](const std::string& text, const std::string& message) {
    const std::string path = write_file(tmp, "bad_motion.csv", text);
    REQUIRE_THROWS_WITH(TabulatedMotion::load(path), Contains(message));
  };
  fails_with("time,roll\n0,1\n", "header must be exactly");
  fails_with(header + "0,0,0,0,0,0,0\n1,0,abc,0,0,0,0\n", ":3: column 'pitch_deg': 'abc' is not a finite number");
  fails_with(header + "0,0,0,0,0,0,0\n0,0,0,0,0,0,0\n", ":3: column 't_s': time must increase strictly");
  fails_with(header + "0,0,0,0,0,0\n", ":2: expected 7 values, found 6");
  fails_with(header + "0,0,0,0,0,0,0\n", "at least two rows");
  fails_with(header + "0,0,0,0,0,0,0\n1,400,0,0,0,0,0\n", "outside [-360, 360] degrees");
  fails_with("", "empty motion record");
  REQUIRE_THROWS_AS(TabulatedMotion::load("/nonexistent/motion.csv"), grainscale::InputError);
}
