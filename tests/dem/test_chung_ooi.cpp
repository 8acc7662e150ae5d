// The particle-impact benchmarks of Chung & Ooi (2011), "Benchmark tests for verifying discrete
// element modelling codes at particle impact level", Granular Matter 13:643-656, for spheres.
// Materials and speeds are those of the paper (tests 1-4; tests 5-8 use its aluminium alloy sphere).
// References: Hertz theory (Johnson 1985) for tests 1-2, the input restitution for test 3,
// rigid-body impulse theory in the gross-sliding regime for tests 4-8 (Maw, Barber & Fawcett 1976;
// Thornton et al. 2011), and for the no-slip limit an independent GSL integration of the
// nondimensional Hertz-Mindlin equations.
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "dem/time_step.hpp"
#include "impact_fixture.hpp"

using namespace grainscale::dem;
using namespace grainscale::dem::testing;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

const Solid kGlass{4.8e10, 0.20, 2800};
const Solid kLimestone{2.0e10, 0.25, 2500};
const Solid kAluminiumAlloy{7.0e10, 0.33, 2699};
const Solid kMagnesiumAlloy{4.0e10, 0.35, 1800};
const Solid kAluminiumOxide{3.8e11, 0.23, 4000};
const Solid kCastIron{1.0e11, 0.25, 7000};

double sphere_mass(const Solid& s, double r) { return s.density * 4.0 / 3.0 * std::numbers::pi * r * r * r; }

struct HertzPrediction {
  double duration, overlap, force;
};
HertzPrediction hertz(double r_eff, double m_eff, double e_eff, double v) {
  const double d = hertz_max_overlap(r_eff, m_eff, e_eff, v);
  return {hertz_contact_time(r_eff, m_eff, e_eff, v), d, 4.0 / 3.0 * e_eff * std::sqrt(r_eff) * std::pow(d, 1.5)};
}

void require_hertz(const ImpactResult& got, const HertzPrediction& want) {
  CHECK_THAT(got.duration, WithinRel(want.duration, 0.02));
  CHECK_THAT(got.max_overlap, WithinRel(want.overlap, 0.02));
  CHECK_THAT(got.max_force, WithinRel(want.force, 0.02));
}

}  // namespace

TEST_CASE("Chung & Ooi test 1: elastic normal impact of two identical spheres", "[dem][contact][chung-ooi]") {
  const Solid s = GENERATE(kGlass, kLimestone);
  const double r = 0.010, v = 10.0;
  MaterialTable mt = impact_materials(s, s, 1.0, 0.35);
  Simulation sim(mt, impact_settings());
  sim.add_sphere(0, r, {-r, 0, 0}, {v, 0, 0});
  sim.add_sphere(0, r, {r, 0, 0}, {-v, 0, 0});
  const ImpactResult got = run_impact(sim);

  const double e_eff = s.youngs / (2 * (1 - s.poisson * s.poisson));
  require_hertz(got, hertz(r / 2, sphere_mass(s, r) / 2, e_eff, 2 * v));
  CHECK_THAT(got.v1.x, WithinRel(-v, 1e-6));  // e = 1: elastic rebound
  CHECK_THAT(got.v2.x, WithinRel(v, 1e-6));
}

TEST_CASE("Chung & Ooi test 2: elastic normal impact of a sphere with a rigid plane", "[dem][contact][chung-ooi]") {
  const Solid s = GENERATE(kAluminiumAlloy, kMagnesiumAlloy);
  const double r = 0.10, v = 0.2;
  const ImpactResult got = sphere_on_wall(impact_materials(s, s, 1.0, 0.0), r, {0, 0, -v}, {});
  const double e_eff = s.youngs / (1 - s.poisson * s.poisson);  // rigid plane
  require_hertz(got, hertz(r, sphere_mass(s, r), e_eff, v));
  CHECK_THAT(got.v1.z, WithinRel(v, 1e-6));
}

TEST_CASE("The contact-frequency diagnostic equals sqrt(S_n / m*) dt at peak overlap", "[dem][contact]") {
  // Sphere on a rigid plane (Chung & Ooi test 2 material): at peak overlap delta_max the normal
  // stiffness is S_n = 2 E* sqrt(R delta_max).
  const double r = 0.10, v = 0.2;
  const MaterialTable mt = impact_materials(kAluminiumAlloy, kAluminiumAlloy, 1.0, 0.0);
  Simulation sim(mt, impact_settings());
  sim.add_sphere(0, r, {0, 0, r}, {0, 0, -v});
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), mt.index("wall"));
  sim.setup();
  double worst = 0;
  for (int s = 0; s < 200000 && sim.particles().v[0].z <= 0; ++s) {
    sim.step();
    worst = std::max(worst, sim.diagnostics().max_omega_dt);
  }
  const double e_eff = kAluminiumAlloy.youngs / (1 - kAluminiumAlloy.poisson * kAluminiumAlloy.poisson);
  const double m = sphere_mass(kAluminiumAlloy, r);
  const double d_max = hertz_max_overlap(r, m, e_eff, v);
  CHECK_THAT(worst, WithinRel(sim.dt() * std::sqrt(2 * e_eff * std::sqrt(r * d_max) / m), 0.01));
}

TEST_CASE("Chung & Ooi test 3: normal impact reproduces the coefficient of restitution", "[dem][contact][chung-ooi]") {
  const Solid s = GENERATE(kAluminiumOxide, kCastIron);
  const double e = GENERATE(0.1, 0.5, 0.9);
  const double r = 0.0025, v = 3.9;
  const ImpactResult got = sphere_on_wall(impact_materials(s, s, e, 0.0), r, {0, 0, -v}, {});
  INFO("e = " << e);
  CHECK_THAT(got.v1.z / v, WithinRel(e, 0.02));
}

namespace {

// The damped Hertz law turns slightly tensile just before separation (that is what makes the
// rebound exactly e), and friction acts only while the contact is compressive. So the impulse that
// friction works against is the compressive part, (1 + e) m v_n c(e) with c(e) >= 1, a property of
// the contact law alone. c(e) comes from the nondimensional normal equation
//   X'' = -X^(3/2) - d sqrt(3/2) X^(1/4) X',  X(0) = 0, X'(0) = 1,
// integrated with GSL: c = (integral of the compressive force) / (1 + e).
double compressive_impulse_factor(double e) {
  const double ln_e = std::log(e);
  double d = -2 * std::sqrt(5.0 / 6.0) * ln_e / std::sqrt(ln_e * ln_e + std::numbers::pi * std::numbers::pi);
  auto rhs = [](double, const double y[], double f[], void* params) -> int {
    const double dd = *static_cast<double*>(params);
    const double x = std::max(y[0], 0.0);
    const double force = -std::pow(x, 1.5) - dd * std::sqrt(1.5) * std::pow(x, 0.25) * y[1];
    f[0] = y[1];
    f[1] = force;
    f[2] = std::max(-force, 0.0);  // compressive impulse so far
    return GSL_SUCCESS;
  };
  gsl_odeiv2_system sys{rhs, nullptr, 3, &d};
  gsl_odeiv2_driver* drv = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-6, 1e-12, 1e-12);
  double y[3] = {0, 1, 0}, t = 0;
  while (!(y[0] < 0 && t > 0.1)) gsl_odeiv2_driver_apply(drv, &t, t + 1e-4, y);
  gsl_odeiv2_driver_free(drv);
  return y[2] / (1 + e);
}

// Rigid-body impulse theory for a sphere hitting a rigid plane while sliding throughout the contact:
// compressive normal impulse m (1 + e) v_n c(e), tangential impulse mu times that, opposing the slip.
struct SlidingRebound {
  double v_t, omega;  // tangential velocity (along x) and spin (about y) after impact
};
SlidingRebound sliding_rebound(double v_n, double v_t, double omega, double r, double e, double mu) {
  const double slip = v_t - omega * r;  // contact-point velocity along x (spin about +y moves the bottom point -x)
  const double j = mu * (1 + e) * compressive_impulse_factor(e) * v_n * (slip > 0 ? 1.0 : -1.0);  // per unit mass
  return {v_t - j, omega + 2.5 * j / r};
}

/// Ratio of contact-point tangential velocity after/before a no-slip (mu -> inf) Hertz-Mindlin impact
/// on a rigid plane, from the nondimensional equations (time scaled by the Hertz time, see
/// docs/contact_models.md):
///   X'' = -X^(3/2) - d sqrt(3/2) X^(1/4) X'
///   Y'' = -(7/2) [ (3/2) kappa X^(1/2) Y + d sqrt((3/2) kappa) X^(1/4) Y' ]
/// with kappa = S_t/S_n = 2(1-nu)/(2-nu), d the damping factor, m/m_t = 7/2 for a solid sphere.
double no_slip_tangential_ratio(double nu, double e) {
  struct P {
    double kappa, d;
  } par{2 * (1 - nu) / (2 - nu), 0};
  const double ln_e = std::log(e);
  par.d = -2 * std::sqrt(5.0 / 6.0) * ln_e / std::sqrt(ln_e * ln_e + std::numbers::pi * std::numbers::pi);
  auto rhs = [](double, const double y[], double f[], void* params) -> int {
    const P& q = *static_cast<P*>(params);
    const double x = std::max(y[0], 0.0);
    f[0] = y[1];
    f[1] = -std::pow(x, 1.5) - q.d * std::sqrt(1.5) * std::pow(x, 0.25) * y[1];
    f[2] = y[3];
    f[3] = -3.5 * (1.5 * q.kappa * std::sqrt(x) * y[2] + q.d * std::sqrt(1.5 * q.kappa) * std::pow(x, 0.25) * y[3]);
    return GSL_SUCCESS;
  };
  gsl_odeiv2_system sys{rhs, nullptr, 4, &par};
  gsl_odeiv2_driver* drv = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-6, 1e-12, 1e-12);
  double y[4] = {0, 1, 0, 1}, t = 0;
  const double h = 1e-4;
  for (;;) {
    double y_prev[4] = {y[0], y[1], y[2], y[3]};
    gsl_odeiv2_driver_apply(drv, &t, t + h, y);
    if (y[0] < 0 && t > 0.1) {  // separation: interpolate linearly to X = 0
      const double a = y_prev[0] / (y_prev[0] - y[0]);
      gsl_odeiv2_driver_free(drv);
      return y_prev[3] + a * (y[3] - y_prev[3]);
    }
  }
}

}  // namespace

TEST_CASE("The damped Hertz law: restitution exact, compressive impulse slightly above (1 + e) m v", "[dem][contact]") {
  // Documents the model property used by the oblique-impact references below.
  CHECK_THAT(compressive_impulse_factor(0.98), WithinRel(1.0, 0.001));
  CHECK(compressive_impulse_factor(0.5) > 1.02);
  CHECK(compressive_impulse_factor(0.1) > compressive_impulse_factor(0.5));
}

TEST_CASE("Chung & Ooi test 4: oblique impact on a plane at constant speed, varying incident angle",
          "[dem][contact][chung-ooi]") {
  // Aluminium oxide sphere, 3.9 m/s, mu = 0.092, e = 0.98 (Chung & Ooi 2011, Table 4).
  const double r = 0.0025, speed = 3.9, mu = 0.092, e = 0.98;
  const MaterialTable mt = impact_materials(kAluminiumOxide, kAluminiumOxide, e, mu);

  SECTION("gross sliding (tan(angle) > 3.5 mu (1 + e)): rigid-body impulse theory") {
    const double angle_deg = GENERATE(40.0, 50.0, 60.0, 70.0, 80.0);
    const double a = angle_deg * std::numbers::pi / 180;
    const double v_n = speed * std::cos(a), v_t = speed * std::sin(a);
    const ImpactResult got = sphere_on_wall(mt, r, {v_t, 0, -v_n}, {});
    const SlidingRebound want = sliding_rebound(v_n, v_t, 0, r, e, mu);
    INFO("incident angle " << angle_deg << " deg");
    CHECK_THAT(got.v1.x / v_t, WithinRel(want.v_t / v_t, 0.02));  // tangential restitution
    CHECK_THAT(got.w1.y, WithinRel(want.omega, 0.02));
    CHECK_THAT(got.v1.z, WithinRel(e * v_n, 0.02));
  }

  SECTION("no-slip limit (mu -> infinity): contact-point velocity ratio of the Mindlin solution") {
    const double e_stick = GENERATE(1.0, 0.98);
    const MaterialTable sticky = impact_materials(kAluminiumOxide, kAluminiumOxide, e_stick, 100.0);
    const double a = 10 * std::numbers::pi / 180;
    const double v_n = speed * std::cos(a), v_t = speed * std::sin(a);
    const ImpactResult got = sphere_on_wall(sticky, r, {v_t, 0, -v_n}, {}, 0.002);
    const double ratio = (got.v1.x - got.w1.y * r) / v_t;
    const double want = no_slip_tangential_ratio(kAluminiumOxide.poisson, e_stick);
    INFO("e = " << e_stick);
    CHECK_THAT(ratio, WithinRel(want, 0.02));
  }
}

TEST_CASE("Chung & Ooi tests 5 and 6: spinning sphere on a plane at constant normal velocity",
          "[dem][contact][chung-ooi]") {
  // Aluminium alloy sphere, v_n = 0.2 m/s, e = 0.5, mu = 0.4; test 5 spin only, test 6 spin against
  // a tangential velocity (backspin), both in the gross-sliding range |v_t + w r| > 3.5 mu (1 + e) v_n.
  const double r = 0.10, v_n = 0.2, e = 0.5, mu = 0.4;
  const MaterialTable mt = impact_materials(kAluminiumAlloy, kAluminiumAlloy, e, mu);
  const double v_t = GENERATE(0.0, 0.5);
  const double w = GENERATE(-25.0, -10.0, 10.0, 25.0);
  const ImpactResult got = sphere_on_wall(mt, r, {v_t, 0, -v_n}, {0, w, 0});
  const SlidingRebound want = sliding_rebound(v_n, v_t, w, r, e, mu);
  INFO("v_t = " << v_t << " m/s, omega = " << w << " rad/s");
  CHECK_THAT(got.v1.x, WithinRel(want.v_t, 0.02));
  CHECK_THAT(got.w1.y, WithinRel(want.omega, 0.02));
  CHECK_THAT(got.v1.z, WithinRel(e * v_n, 0.02));
}

TEST_CASE("Chung & Ooi tests 7 and 8: two spheres, equal and unequal, spinning or sliding",
          "[dem][contact][chung-ooi]") {
  // Aluminium alloy; test 7 two identical spheres with opposite spins, test 8 a sphere of half the
  // radius with a tangential velocity. Gross sliding throughout; impulse theory for two bodies.
  const double e = 0.5, mu = 0.4, v_n = 0.2;
  const double r1 = 0.10;
  const double r2 = GENERATE(0.10, 0.05);
  const double w = GENERATE(10.0, 30.0);
  const double v_t2 = r2 < r1 ? -0.8 : 0.0;
  MaterialTable mt = impact_materials(kAluminiumAlloy, kAluminiumAlloy, e, mu);
  Simulation sim(mt, impact_settings());
  // Sphere 1 moves +x onto sphere 2; tangential direction y, spins about z.
  sim.add_sphere(0, r1, {-r1, 0, 0}, {v_n / 2, 0, 0}, {0, 0, w});
  sim.add_sphere(1, r2, {r2, 0, 0}, {-v_n / 2, v_t2, 0}, {0, 0, r2 < r1 ? 0.0 : w});
  const ImpactResult got = run_impact(sim);

  const double m1 = sphere_mass(kAluminiumAlloy, r1), m2 = sphere_mass(kAluminiumAlloy, r2);
  const double m_eff = m1 * m2 / (m1 + m2);
  // Contact point velocity of 1 relative to 2 along y: v1y - v2y + (w1 x (r1 e_x)).y - (w2 x (-r2 e_x)).y
  const double w2 = r2 < r1 ? 0.0 : w;
  const double slip = -v_t2 + w * r1 + w2 * r2;
  const double jn = (1 + e) * compressive_impulse_factor(e) * m_eff * v_n;
  const double jt = mu * jn * (slip > 0 ? 1.0 : -1.0);  // impulse on 1 along -y
  INFO("r2 = " << r2 << ", omega = " << w);
  CHECK_THAT(got.v1.y, WithinAbs(-jt / m1, 0.02 * std::abs(jt / m1)));
  CHECK_THAT(got.v2.y, WithinRel(v_t2 + jt / m2, 0.02));
  CHECK_THAT(got.w1.z, WithinRel(w - jt * r1 / (0.4 * m1 * r1 * r1), 0.02));
  CHECK_THAT(got.w2.z, WithinRel(w2 - jt * r2 / (0.4 * m2 * r2 * r2), 0.02));
  // Linear momentum is conserved to round-off.
  const double p_before_x = m1 * v_n / 2 - m2 * v_n / 2, p_before_y = m2 * v_t2;
  CHECK(std::abs(m1 * got.v1.x + m2 * got.v2.x - p_before_x) < 1e-12 * m1 * v_n);
  CHECK(std::abs(m1 * got.v1.y + m2 * got.v2.y - p_before_y) < 1e-12 * m1 * v_n);
}
