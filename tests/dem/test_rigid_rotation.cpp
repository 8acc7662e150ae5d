// The free asymmetric top (Landau & Lifshitz, Mechanics, Sec. 37): rotation about the axes of least
// and greatest inertia is stable, about the intermediate axis it is not (the body flips over and back
// periodically: the Dzhanibekov effect). Energy and |L| are constants of the motion.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <numbers>
#include <vector>

#include "dem/rigid_rotation.hpp"
#include "dem/rotation_batch.hpp"

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

TEST_CASE("A spinning sphere turns by |omega| t about omega, at small and large angles per step", "[rotation]") {
  // An isotropic body's free rotation is one exact turn per step; its half angle's sine and cosine
  // come from the series below 0.01 rad and from libm above, so both must accumulate to the exact
  // orientation: after n steps, q = rot(omega_hat, |omega| n h) q0 to round-off.
  const double half_angle = GENERATE(1e-6, 1e-4, 0.009, 0.011, 0.4);  // per step
  const Vec3 inertia{2e-9, 2e-9, 2e-9};
  const Vec3 axis = (1.0 / norm(Vec3{1, -2, 0.5})) * Vec3{1, -2, 0.5};
  const double h = 1e-5, w = 2 * half_angle / h;
  const Vec3 L = (inertia.x * w) * axis;
  const Quat q0 = normalized({0.9, 0.1, -0.3, 0.2});
  Quat q = q0;
  const int n = 1000;
  for (int s = 0; s < n; ++s) free_rotation_step(q, L, inertia, h);
  const double total = n * half_angle;  // half of the whole turn
  const Quat turn{std::cos(total), std::sin(total) * axis.x, std::sin(total) * axis.y, std::sin(total) * axis.z};
  const Quat exact = turn * q0;
  const double sign = q.w * exact.w + q.x * exact.x + q.y * exact.y + q.z * exact.z < 0 ? -1 : 1;  // q ~ -q
  INFO("half angle per step " << half_angle);
  CHECK(std::abs(q.w - sign * exact.w) < 1e-12);
  CHECK(std::abs(q.x - sign * exact.x) < 1e-12);
  CHECK(std::abs(q.y - sign * exact.y) < 1e-12);
  CHECK(std::abs(q.z - sign * exact.z) < 1e-12);
  Quat still = q0;
  free_rotation_step(still, {0, 0, 0}, inertia, h);  // no spin: no turn
  CHECK(still.w == q0.w);
  CHECK(still.x == q0.x);
}

namespace {
// One body at a time, out of line so that the compiler cannot vectorise it with the batch.
[[gnu::noinline]] void rotate_one(Quat& q, Vec3& omega, const Vec3& L, const Vec3& inertia, double h) {
  free_rotation_step(q, L, inertia, h);
  omega = angular_velocity(q, L, inertia);
}
// An isotropic body as drift turned it one at a time: omega = (1 / I) L, one exact turn about it.
[[gnu::noinline]] void turn_one_sphere(Quat& q, Vec3& omega, const Vec3& L, double moment, double h) {
  omega = (1.0 / moment) * L;
  free_rotation_isotropic(q, omega, h);
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Spheres' orientations, angular momenta and moments of inertia, drawn from `seed`: spin rates over
/// three decades (~30 to ~3 x 10^4 rad/s, half angles per step of 1e-4 s from ~1e-3 to ~1, both sides
/// of the series' range, 0.01), and every ninth sphere without spin, its orientation a little off
/// unit length as after many steps (normalising it again would change its bits).
struct Spheres {
  std::vector<Quat> q;
  std::vector<Vec3> L;
  std::vector<double> moment;
};
Spheres random_spheres(unsigned seed, int count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Spheres s;
  for (int c = 0; c < count; ++c) {
    const bool still = c % 9 == 0;
    s.q.push_back(still ? Quat{0.5, 0.5, 0.5, 0.5000000001} : normalized(Quat{u(rng), u(rng), u(rng), u(rng)}));
    s.moment.push_back(1e-9 * (2 + u(rng)));
    s.L.push_back(still ? Vec3{} : 1e-9 * std::pow(10.0, 3 + 1.5 * u(rng)) * Vec3{u(rng), u(rng), u(rng)});
  }
  return s;
}
}  // namespace

TEST_CASE("A vectorised batch of free rotations gives free_rotation_step's numbers bit for bit", "[rotation]") {
  // Simulation::drift turns its bodies a RotationBatch at a time; the batch must reproduce one body
  // at a time exactly (same operations, no FMA), and flag the bodies that turn beyond the sine
  // series' range in a step (drift then takes the general path for them).
  std::mt19937_64 rng(GENERATE(1u, 2u, 3u));
  std::uniform_real_distribution<double> u(-1, 1);
  const double h = 1e-4;
  RotationBatch batch;
  std::vector<Quat> q0;
  std::vector<Vec3> L, inertia;
  for (int c = 0; c < RotationBatch::kCapacity - 3; ++c) {  // not a whole number of vector lanes
    const Quat q = normalized(Quat{u(rng), u(rng), u(rng), u(rng)});
    const Vec3 I{1e-9 * (1.5 + u(rng)), 1e-9 * (2.5 + u(rng)), 1e-9 * (3.5 + u(rng))};
    // Spin rates spread over three decades (~10 to ~10^4 rad/s): half angles per sub-step from
    // ~1e-4 to ~0.5, both sides of the series' range (0.01).
    const Vec3 l = 1e-9 * std::pow(10.0, 2.5 + 1.5 * u(rng)) * Vec3{u(rng), u(rng), u(rng)};
    q0.push_back(q), L.push_back(l), inertia.push_back(I);
    batch.add(static_cast<std::uint32_t>(c), q, l, I);
  }
  batch.rotate(h);
  int in_range = 0;
  for (int c = 0; c < batch.size; ++c) {
    Quat q = q0[c];
    Vec3 w;
    rotate_one(q, w, L[c], inertia[c], h);
    if (!batch.in_range[c]) continue;  // drift recomputes these with free_rotation_step
    ++in_range;
    INFO("body " << c);
    CHECK(same_bits(batch.qw[c], q.w));
    CHECK(same_bits(batch.qx[c], q.x));
    CHECK(same_bits(batch.qy[c], q.y));
    CHECK(same_bits(batch.qz[c], q.z));
    CHECK(same_bits(batch.wx[c], w.x));
    CHECK(same_bits(batch.wy[c], w.y));
    CHECK(same_bits(batch.wz[c], w.z));
  }
  INFO(in_range << " of " << batch.size << " in the series' range");
  CHECK(in_range > batch.size / 4);   // both kinds present, so both paths are checked
  CHECK(in_range < batch.size * 3 / 4);
}

TEST_CASE("A vectorised batch of isotropic turns gives free_rotation_step's numbers bit for bit", "[rotation]") {
  // Simulation::drift turns its spheres (isotropic bodies) an IsotropicRotationBatch at a time: the
  // batch must reproduce one body at a time exactly, leave a body without spin as it was (not
  // normalised again), and flag those that turn beyond the sine series' range in a step (drift then
  // takes free_rotation_isotropic for them).
  const int count = IsotropicRotationBatch::kCapacity - 3;  // not a whole number of vector lanes
  const Spheres spheres = random_spheres(GENERATE(1u, 2u, 3u), count);
  const double h = 1e-4;
  IsotropicRotationBatch batch;
  for (int c = 0; c < count; ++c) batch.add(static_cast<std::uint32_t>(c), spheres.q[c], spheres.L[c], spheres.moment[c]);
  batch.rotate(h);
  int in_range = 0, still = 0;
  for (int c = 0; c < batch.size; ++c) {
    Quat q = spheres.q[c];
    Vec3 w;
    turn_one_sphere(q, w, spheres.L[c], spheres.moment[c], h);
    INFO("sphere " << c);
    // omega whether in range or not (drift stores it as it is); the orientation where in range
    // (drift recomputes the others with free_rotation_isotropic).
    CHECK((same_bits(batch.wx[c], w.x) && same_bits(batch.wy[c], w.y) && same_bits(batch.wz[c], w.z)));
    if (!batch.in_range[c]) continue;
    ++in_range;
    if (spheres.L[c] == Vec3{}) {  // without spin: the orientation as it was, bit for bit (not normalised again)
      ++still;
      const Quat& before = spheres.q[c];
      CHECK((same_bits(batch.qw[c], before.w) && same_bits(batch.qx[c], before.x) &&
             same_bits(batch.qy[c], before.y) && same_bits(batch.qz[c], before.z)));
    }
    CHECK((same_bits(batch.qw[c], q.w) && same_bits(batch.qx[c], q.x) && same_bits(batch.qy[c], q.y) &&
           same_bits(batch.qz[c], q.z)));
  }
  INFO(in_range << " of " << batch.size << " in the series' range, " << still << " without spin");
  CHECK(still == (batch.size + 8) / 9);  // spheres without spin are in range, and kept as they were
  CHECK(in_range > batch.size / 4);      // both kinds present, so both paths are checked
  CHECK(in_range < batch.size * 3 / 4);
}
