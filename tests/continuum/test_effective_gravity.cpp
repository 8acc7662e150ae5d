// The cycle-mean anomaly of the effective gravity off a rotation axis (continuum/terms/
// effective_gravity.hpp, (G1)-(G3)), against what follows from g_eff = g − α×r − ω×(ω×r) by hand:
// the centrifugal limit, the normal component's exact mean, the leading-order cancellation of the
// centrifugal lean by the Euler term's rectification for a small harmonic swing, the mirror symmetry
// about the axis, and the friction threshold.
#include <catch2/catch.hpp>
#include <cmath>

#include "continuum/terms/effective_gravity.hpp"

using namespace grainscale::continuum;

namespace {
constexpr double g = 9.81;
/// The harmonic θ = A sin(Ω t) as the cycle means the term takes.
CycleMotion harmonic(double amplitude_deg, double frequency_hz, double axis_x, double axis_z, double mu = 0) {
  const double A = amplitude_deg * M_PI / 180, w = 2 * M_PI * frequency_hz;
  return {A * A * w * w / 2, A * A * w * w * w * w / 2, axis_x, axis_z, mu};
}
}  // namespace

TEST_CASE("Without angular acceleration the anomaly is the centrifugal lean <w^2> r / g", "[continuum][loop][lever_arm]") {
  const CycleMotion m{0.5, 0.0, -1.0, -0.3, 0.0};
  const auto [ax, az] = effective_gravity_anomaly(m, 0.2, 0.05);
  CHECK(ax == Approx(0.5 * 1.2 / g).epsilon(1e-12));
  CHECK(az == Approx(0.5 * 0.35 / g).epsilon(1e-12));
}

TEST_CASE("The normal component's anomaly is <w^2> r_z / g for any swing (the Euler part averages out)", "[continuum][loop][lever_arm]") {
  const double amplitude = GENERATE(5.0, 20.0, 35.0);
  const CycleMotion m = harmonic(amplitude, 0.5, -0.8, -0.2);
  for (const double z : {0.0, 0.05, 0.1}) {
    const auto [ax, az] = effective_gravity_anomaly(m, 0.1, z);
    (void)ax;
    CHECK(az == Approx(m.omega2 * (z + 0.2) / g).epsilon(1e-9));
  }
}

TEST_CASE("A small swing: the Euler term's rectified slope cancels the centrifugal lean at leading order", "[continuum][loop][lever_arm]") {
  // e ≈ θ + θ'² r_x / g − Ω² θ² r_x / g: the mean is (⟨ω²⟩ − Ω² A²/2) r_x / g = 0; what is left is O(A⁴).
  // Halving A must cut the ratio to the centrifugal lean about four times.
  double previous = 0;
  for (const double amplitude : {8.0, 4.0, 2.0}) {
    const CycleMotion m = harmonic(amplitude, 0.5, -0.9, 0.0);
    const double centrifugal = m.omega2 * 0.9 / g;
    const double ratio = effective_gravity_anomaly(m, 0.0, 0.0, 512).first / centrifugal;
    INFO("A = " << amplitude << " deg: a_x / centrifugal = " << ratio);
    CHECK(std::abs(ratio) < 0.05);
    if (previous != 0) CHECK(std::abs(previous / ratio) == Approx(4).epsilon(0.1));
    previous = ratio;
  }
}

TEST_CASE("A wide swing far off the axis leans the bed towards the axis, mirrored on the other side", "[continuum][loop][lever_arm]") {
  // studies/loop_lever_arm/off_axis.yaml: ±35° at 0.5 Hz, the box 0.8–1.0 m from the axis. At the
  // swing's end towards the axis the normal load is g cos A − Ω² A r_x (0.27 g at r = 0.9 m) and
  // the slope 2.1; at the other end 0.42: the mean slope leans towards the axis despite the
  // centrifugal +0.17.
  const CycleMotion right = harmonic(35, 0.5, -0.8, 0.0), left = harmonic(35, 0.5, 0.8 + 0.2, 0.0);
  for (const double d : {0.8, 0.9, 1.0}) {
    const double ax = effective_gravity_anomaly(right, d - 0.8, 0.0).first;
    INFO("r = " << d << ": a_x = " << ax);
    CHECK(ax < -0.08);
    CHECK(ax > -0.3);
    // The box on the other side of the axis (axis at its right): mirrored.
    CHECK(effective_gravity_anomaly(left, 1.0 - d, 0.0).first == Approx(-ax).epsilon(1e-9));
  }
  CHECK(effective_gravity_anomaly(right, 0.2, 0.0).first < effective_gravity_anomaly(right, 0.0, 0.0).first);  // grows with the arm
  // On the axis there is no lean.
  CHECK(effective_gravity_anomaly(right, -0.8, 0.0).first == Approx(0).margin(1e-12));
}

TEST_CASE("Static friction: no lean while the slope never exceeds mu, more than the mean slope beyond it", "[continuum][loop][lever_arm]") {
  // Max |e| at r = 0.9 m, ±35°, 0.5 Hz is about 2.1 (weak end) and 0.42 (strong end).
  const CycleMotion sticky = harmonic(35, 0.5, -0.9, 0.0, 3.0);
  CHECK(effective_gravity_anomaly(sticky, 0.0, 0.0).first == 0);
  const double mean_slope = effective_gravity_anomaly(harmonic(35, 0.5, -0.9, 0.0, 0.0), 0.0, 0.0).first;
  const double above_repose = effective_gravity_anomaly(harmonic(35, 0.5, -0.9, 0.0, std::tan(28 * M_PI / 180)), 0.0, 0.0).first;
  INFO("mean slope " << mean_slope << ", above repose " << above_repose);
  CHECK(above_repose < mean_slope);  // only the weak end flows: more one-sided
  CHECK(std::isfinite(effective_gravity_anomaly(harmonic(35, 2.0, -5.0, 0.0), 0.0, 0.0).first));  // lifted off: capped
}

TEST_CASE("The tabulated anomaly matches the direct one inside the table", "[continuum][loop][lever_arm]") {
  const CycleMotion m = harmonic(35, 0.5, -0.8, 0.0, 0.3);
  const AnomalyTable t(m, 0.0, 0.2, 0.0, 0.2);
  double worst = 0;
  for (double x = 0.003; x < 0.2; x += 0.017) {
    for (double z = 0.001; z < 0.1; z += 0.013) {
      const auto [ax, az] = effective_gravity_anomaly(m, x, z);
      const auto [tx, tz] = t.at(x, z);
      worst = std::max({worst, std::abs(tx - ax), std::abs(tz - az)});
    }
  }
  INFO("worst difference " << worst);
  CHECK(worst < 2e-3);
  CHECK(t.covers(0, 0.2, 0, 0.1));
  CHECK_FALSE(t.covers(0, 0.3, 0, 0.1));
}
