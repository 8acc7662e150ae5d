// The free asymmetric top (Landau & Lifshitz, Mechanics, Sec. 37): rotation about the axes of least
// and greatest inertia is stable, about the intermediate axis it is not (the body flips over and back
// periodically: the Dzhanibekov effect). Energy and |L| are constants of the motion.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "dem/rigid_rotation.hpp"

using namespace grainscale::dem;

namespace {

const Vec3 kInertia{1.0, 2.0, 3.0};

struct TopRun {
  double energy_drift;     // |mean E over the last 10 % - mean E over the first 10 %| / E0
  double energy_wobble;    // max |E - E0| / E0
  double momentum_error;   // max | |L_body| - |L| | / |L|  (L_world is exact by construction)
  double min_axis_share;   // min over time of Lb_k / |L| along the initial spin axis k
  double max_axis_share;
};

/// Spin mainly about body axis k (rate w), slightly perturbed, for `periods` spin periods.
TopRun spin(int k, double periods, int steps_per_period) {
  const double w = 2 * std::numbers::pi;  // one turn per unit time about the main axis
  Vec3 omega_body{1e-3 * w, 1e-3 * w, 1e-3 * w};
  (k == 0 ? omega_body.x : k == 1 ? omega_body.y : omega_body.z) = w;
  Quat q = normalized({0.9, 0.1, -0.3, 0.2});  // an arbitrary initial orientation
  const Vec3 lb0{kInertia.x * omega_body.x, kInertia.y * omega_body.y, kInertia.z * omega_body.z};
  const Vec3 L = rotate(q, lb0);
  const double e0 = rotational_energy(q, L, kInertia);
  const double h = 1.0 / steps_per_period;
  const auto n = static_cast<long>(periods * steps_per_period);
  TopRun r{0, 0, 0, 1, -1};
  double early = 0, late = 0;
  const long window = n / 10;
  for (long s = 0; s < n; ++s) {
    free_rotation_step(q, L, kInertia, h);
    const double e = rotational_energy(q, L, kInertia);
    if (s < window) early += e;
    if (s >= n - window) late += e;
    r.energy_wobble = std::max(r.energy_wobble, std::abs(e - e0) / e0);
    const Vec3 lb = to_body(q, L);
    r.momentum_error = std::max(r.momentum_error, std::abs(norm(lb) - norm(L)) / norm(L));
    const double share = (k == 0 ? lb.x : k == 1 ? lb.y : lb.z) / norm(L);
    r.min_axis_share = std::min(r.min_axis_share, share);
    r.max_axis_share = std::max(r.max_axis_share, share);
  }
  r.energy_drift = std::abs(late - early) / window / e0;
  return r;
}

}  // namespace

TEST_CASE("A free asymmetric top keeps its energy and angular momentum over 1,000 rotations", "[dem][rigid]") {
  const int axis = GENERATE(0, 1, 2);
  const TopRun r = spin(axis, 1000, 400);
  INFO("axis " << axis << ": energy drift " << r.energy_drift << ", wobble " << r.energy_wobble);
  CHECK(r.energy_drift < 1e-6);
  CHECK(r.energy_wobble < 1e-5);  // bounded O(h^2) oscillation of a symplectic method
  CHECK(r.momentum_error < 1e-12);
}

TEST_CASE("Rotation about the intermediate axis flips; about the major and minor axes it does not", "[dem][rigid]") {
  SECTION("least inertia: stable") {
    const TopRun r = spin(0, 200, 400);
    CHECK(r.min_axis_share > 0.99);
  }
  SECTION("greatest inertia: stable") {
    const TopRun r = spin(2, 200, 400);
    CHECK(r.min_axis_share > 0.99);
  }
  SECTION("intermediate inertia: flips over") {
    const TopRun r = spin(1, 200, 400);
    CHECK(r.max_axis_share > 0.99);
    CHECK(r.min_axis_share < -0.99);  // the spin axis has turned upside down
  }
}

TEST_CASE("The rotation integrator converges at second order", "[dem][rigid]") {
  // Orientation error after one time unit against a reference with 64x smaller steps.
  auto run = [](int steps) {
    Quat q{};
    const Vec3 L = rotate(q, Vec3{kInertia.x * 1.0, kInertia.y * 3.0, kInertia.z * 0.5});
    for (int s = 0; s < steps; ++s) free_rotation_step(q, L, kInertia, 1.0 / steps);
    return q;
  };
  const Quat ref = run(64 * 400);
  auto err = [&](const Quat& q) {
    const double d = std::abs(q.w * ref.w + q.x * ref.x + q.y * ref.y + q.z * ref.z);
    return std::sqrt(std::max(0.0, 2 * (1 - d)));
  };
  const double e1 = err(run(100)), e2 = err(run(200));
  const double rate = std::log2(e1 / e2);
  INFO("errors " << e1 << ", " << e2 << ", rate " << rate);
  CHECK(rate > 2 - 0.1);
}

TEST_CASE("The sub-step's sine and cosine agree with libm to round-off at every angle", "[rotation]") {
  // detail::sin_cos switches from a Taylor series to libm at |x| = 0.01: both sides of the switch,
  // tiny angles and large ones must give the libm values within 2 units in the last place.
  auto ulps = [](double a, double b) { return std::abs(a - b) / std::max(std::nextafter(std::abs(b), 1e300) - std::abs(b), 1e-300); };
  const double xs[] = {0.0, 1e-300, 1e-12, 3e-6, 1e-4, 2.5e-3, 0.0099999, 0.01, 0.0100001, 0.3, 2.0, -1e-4, -0.0099};
  for (double x : xs) {
    double s = 0, c = 0;
    detail::sin_cos(x, s, c);
    INFO("x = " << x);
    CHECK(ulps(s, std::sin(x)) <= 2);
    CHECK(ulps(c, std::cos(x)) <= 2);
  }
  for (int k = 1; k <= 1000; ++k) {  // a dense sweep below the switch, where the series is used
    const double x = 1e-5 * k;
    double s = 0, c = 0;
    detail::sin_cos(x, s, c);
    REQUIRE(ulps(s, std::sin(x)) <= 2);
    REQUIRE(ulps(c, std::cos(x)) <= 2);
  }
}
