// Savage–Hutter's earth-pressure coefficient in the flow closure (continuum/closure/earth_pressure.hpp,
// (K1)): its closed-form limits, and the bed it leaves piled against a wall on a tilted floor.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "closure_fixture.hpp"
#include "dem/motion/platform_tilt.hpp"

using namespace grainscale::continuum::closure;
using namespace closure_test;

TEST_CASE("earth pressure: Savage-Hutter's K has Rankine's values on a frictionless floor and one value at delta = phi",
          "[closure][earth_pressure]") {
  const double phi = GENERATE(20.0, 28.36, 35.0);
  const double s = std::sin(phi * kDeg);
  const EarthPressure rankine = EarthPressure::savage_hutter(phi * kDeg, 0);
  CHECK(rankine.active == Approx((1 - s) / (1 + s)).epsilon(1e-12));
  CHECK(rankine.passive == Approx((1 + s) / (1 - s)).epsilon(1e-12));
  const EarthPressure rough = EarthPressure::savage_hutter(phi * kDeg, phi * kDeg);
  CHECK(rough.active == Approx((1 + s * s) / (1 - s * s)).epsilon(1e-12));
  CHECK(rough.passive == Approx(rough.active).epsilon(1e-12));
  // Beyond δ = φ it stays there; in between, active < 1 < passive and both move towards the δ = φ value.
  const EarthPressure rougher = EarthPressure::savage_hutter(phi * kDeg, (phi + 5) * kDeg);
  CHECK(rougher.active == Approx(rough.active).epsilon(1e-12));
  const EarthPressure mid = EarthPressure::savage_hutter(phi * kDeg, 0.5 * phi * kDeg);
  CHECK(mid.active < 1);
  CHECK(mid.passive > 1);
  CHECK(mid.active > rankine.active);
  CHECK(mid.passive < rankine.passive);
  // Strain rate picks the branch.
  CHECK(mid.at(1e-3) == mid.active);
  CHECK(mid.at(-1e-3) == mid.passive);
  CHECK(mid.at(0) == 1.0);
  CHECK(EarthPressure::hydrostatic().at(-1) == 1.0);
}

TEST_CASE("earth pressure: a bed against a wall is held while some K between active and passive holds it",
          "[closure][earth_pressure]") {
  // A plug (ℓ = ∞) filling a 1 m section on a floor tilted by θ = 25° with δ = 15°, its surface sloping
  // by h_x relative to the floor (deeper at the low, +x, wall). At rest it is held while
  // |g_t − K g_n h_x| ≤ g_n tan δ for some K in [K_act, K_pass]: down to h_x = (tan θ − tan δ)/K_pass
  // with Savage–Hutter's K, down to tan θ − tan δ with K = 1 (hydrostatic).
  const double theta = 25 * kDeg, excess = std::tan(theta) - std::tan(15 * kDeg);
  const double k_pass = EarthPressure::savage_hutter(30 * kDeg, 15 * kDeg).passive;
  for (const bool sh : {false, true}) {
    const double critical = sh ? excess / k_pass : excess;
    for (const double factor : {1.001, 0.99}) {
      SectionSettings s = section(1.0, 100, 30, 15, INFINITY);
      s.friction.savage_hutter_pressure = sh;
      std::vector<double> h(s.nx);
      for (int i = 0; i < s.nx; ++i) h[i] = 0.01 + factor * critical * (i + 0.5) * s.length / s.nx;
      ShallowGranularFlow flow(s, tilted(theta), h);
      flow.advance(2.0);
      CAPTURE(sh, factor, critical);
      if (factor > 1) {
        CHECK(flow.depth() == h);  // bit for bit
      } else {
        CHECK(flow.depth() != h);
      }
    }
  }
}

namespace {

/// The dam break of test_closure_flow.cpp (Mangeney, Heinrich & Roche 2000, eq. 14-15) with an earth
/// pressure K: the pressure K g_n h²/2 makes the wave speed √(K g_n h), so the solution is theirs with
/// g_n replaced by K g_n in c0 and in h = (2 c0 − ξ/t + m t/2)² / (9 K g_n). The rarefaction extends
/// the bed everywhere (∂u/∂x > 0): Savage–Hutter's K is the active one.
double dam_break_error(bool savage_hutter, double K_expected, int nx = 400) {
  const double L = 4, x0 = 1.5, h0 = 0.05, theta = 25 * kDeg, delta = 15 * kDeg, t_end = 0.3, g = 9.81;
  SectionSettings s = section(L, nx, 30, 15, INFINITY);
  s.cfl = 0.4;
  s.friction.savage_hutter_pressure = savage_hutter;
  std::vector<double> h(nx);
  for (int i = 0; i < nx; ++i) h[i] = (i + 0.5) * L / nx < x0 ? h0 : 0.0;
  ShallowGranularFlow flow(s, tilted(theta), h);
  flow.advance(t_end);
  const double gn = K_expected * g * std::cos(theta);
  const double c0 = std::sqrt(gn * h0), m = g * (std::sin(theta) - std::cos(theta) * std::tan(delta));
  double err = 0;
  for (int i = 0; i < nx; ++i) {
    const double x = (i + 0.5) * L / nx, xi = x - x0;
    if (x < 0.5) continue;  // the rarefaction from the upper wall, not part of the solution
    double exact = 0;
    if (xi <= -c0 * t_end + 0.5 * m * t_end * t_end) {
      exact = h0;
    } else if (xi < 2 * c0 * t_end + 0.5 * m * t_end * t_end) {
      const double r = 2 * c0 - xi / t_end + 0.5 * m * t_end;
      exact = r * r / (9 * gn);
    }
    err += std::abs(flow.depth()[i] - exact) * L / nx;
  }
  return err / h0;
}

}  // namespace

TEST_CASE("earth pressure: a dam break with Savage-Hutter's K spreads at the active wave speed", "[closure][earth_pressure]") {
  const double k_act = EarthPressure::savage_hutter(30 * kDeg, 15 * kDeg).active;
  const double sh = dam_break_error(true, k_act), sh_vs_hydrostatic = dam_break_error(true, 1.0),
               hydrostatic = dam_break_error(false, 1.0);
  INFO("L1 error / h0: Savage-Hutter vs its solution (K_act = " << k_act << ") " << sh << ", vs the K = 1 solution "
                                                                  << sh_vs_hydrostatic << "; hydrostatic vs K = 1 " << hydrostatic);
  CHECK(sh < 0.015);                    // as the hydrostatic closure against its own solution (1.2 % at 400 cells)
  CHECK(hydrostatic == Approx(sh).epsilon(0.5));
  CHECK(sh_vs_hydrostatic > 1.5 * sh);  // it is not the K = 1 solution
  CHECK(dam_break_error(true, k_act, 200) > 1.3 * sh);  // and converges to its own (order 0.6-0.7: a wet/dry front)
}
