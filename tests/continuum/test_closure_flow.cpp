// The depth-averaged flow closure (continuum/closure/shallow_granular_flow.hpp) against analytic
// results: Coulomb yield (exact rest below the threshold), the repose angle reached by slow tilting,
// the dam break with Coulomb friction on an incline (Mangeney, Heinrich & Roche 2000), steady μ(I)
// flow on an incline (Pouliquen & Forterre 2002), mass conservation and positivity.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numeric>

#include "closure_fixture.hpp"
#include "dem/motion/platform_tilt.hpp"

using namespace grainscale::continuum::closure;
using namespace closure_test;

TEST_CASE("closure: a bed below the Coulomb threshold stays exactly at rest", "[closure][coulomb]") {
  // Deep bed (h ≫ ℓ), floor tilted 20°, surface sloping so that the surface is at 25° to the
  // horizontal (below φ = 26.7°), and a plug bed (ℓ = ∞) at 13° on a floor with δ = 14°.
  for (const bool deep : {true, false}) {
    const double theta = (deep ? 20 : 13) * kDeg;
    SectionSettings s = deep ? section(10, 50, 26.7, 14, 0.04) : section(1, 50, 26.7, 14, INFINITY);
    std::vector<double> h(s.nx);
    const double beta = deep ? -5 * kDeg : 0;  // surface slope relative to the floor
    for (int i = 0; i < s.nx; ++i) h[i] = (deep ? 5.0 : 0.01) + std::tan(beta) * (i + 0.5) * s.length / s.nx + (deep ? 3 : 0);
    ShallowGranularFlow flow(s, tilted(theta), h);
    flow.advance(100.0);
    CAPTURE(deep);
    CHECK(flow.depth() == h);  // bit for bit
    for (double u : flow.surface_speed()) CHECK(u == 0.0);
    CHECK(flow.steps() > 10);
  }
}

TEST_CASE("closure: just above the threshold the bed moves", "[closure][coulomb]") {
  SectionSettings s = section(1, 50, 26.7, 14, INFINITY);
  ShallowGranularFlow flow(s, tilted(14.2 * kDeg), std::vector<double>(s.nx, 0.01));
  flow.advance(1.0);
  const double umax = *std::max_element(flow.surface_speed().begin(), flow.surface_speed().end());
  // Uniform acceleration m = g (sin θ − cos θ tan δ) away from the walls' influence.
  const double m = 9.81 * (std::sin(14.2 * kDeg) - std::cos(14.2 * kDeg) * std::tan(14 * kDeg));
  CHECK(umax == Approx(m * 1.0).epsilon(0.02));
}

TEST_CASE("closure: slow tilting leaves a deep bed's surface at the internal friction angle", "[closure][coulomb]") {
  // Tilt to 35° over 60 s (quasi-static) and hold: the surface in the middle of the container must
  // stand at φ to the horizontal (exact yield condition of a planar surface, (S3)).
  SectionSettings s = section(4, 80, 26.7, 14, 0.02);
  s.friction.delta_mu = 0.26;  // damping of the avalanches (Jop et al. 2005)
  s.friction.grain_diameter = 2e-3;
  dem::PlatformTilt::Params p;
  p.amplitude = 35 * kDeg;
  p.frequency = 1.0 / 120;  // ramp over 60 s
  p.pause = 1e4;
  ContainerPlacement place;
  ShallowGranularFlow flow(s, ContainerGravity(std::make_shared<dem::PlatformTilt>(p), place),
                           std::vector<double>(s.nx, 1.5));
  flow.advance(150.0);
  double worst = 0;
  for (int f = 20; f <= 60; ++f) {
    const double slope = (flow.depth()[f] - flow.depth()[f - 1]) / flow.dx();
    const double angle = 35 * kDeg - std::atan(slope);
    worst = std::max(worst, std::abs(angle / kDeg - 26.7));
  }
  INFO("largest deviation of the surface angle from phi in the middle: " << worst << " deg");
  CHECK(worst < 0.3);
  for (double u : flow.surface_speed()) CHECK(std::abs(u) < 1e-3);
}

namespace {

/// Mangeney, Heinrich & Roche (Pure Appl. Geophys. 157, 2000), eq. (14)–(15): dam break of a
/// reservoir of depth h0 (x < x0) on a plane inclined at θ with Coulomb friction δ < θ:
///   h = (2 c0 − ξ/t + m t / 2)² / (9 g cos θ),  u = 2/3 (ξ/t + c0 + m t),  ξ = x − x0,
/// for −c0 t + m t²/2 < ξ < 2 c0 t + m t²/2; c0 = √(g cos θ h0), m = g (sin θ − cos θ tan δ).
double mangeney_depth(double x, double t, double x0, double h0, double theta, double delta) {
  const double g = 9.81, gn = g * std::cos(theta);
  const double c0 = std::sqrt(gn * h0), m = g * (std::sin(theta) - std::cos(theta) * std::tan(delta));
  const double xi = x - x0;
  if (xi <= -c0 * t + 0.5 * m * t * t) return h0;
  if (xi >= 2 * c0 * t + 0.5 * m * t * t) return 0;
  const double r = 2 * c0 - xi / t + 0.5 * m * t;
  return r * r / (9 * gn);
}

double dam_break_error(int nx) {
  const double L = 4, x0 = 1.5, h0 = 0.05, theta = 25 * kDeg, delta = 15 * kDeg, t_end = 0.3;
  SectionSettings s = section(L, nx, 30, 15, INFINITY);
  s.cfl = 0.4;
  std::vector<double> h(nx);
  for (int i = 0; i < nx; ++i) h[i] = (i + 0.5) * L / nx < x0 ? h0 : 0.0;
  ShallowGranularFlow flow(s, tilted(theta), h);
  flow.advance(t_end);
  double err = 0;
  for (int i = 0; i < nx; ++i) {
    const double x = (i + 0.5) * L / nx;
    if (x < 0.5) continue;  // the rarefaction from the upper wall, not part of the solution
    err += std::abs(flow.depth()[i] - mangeney_depth(x, t_end, x0, h0, theta, delta)) * L / nx;
  }
  return err / (h0 * 1.0);  // relative to the reservoir's depth × 1 m
}

}  // namespace

TEST_CASE("closure: dam break on an incline with Coulomb friction matches Mangeney et al. (2000)",
          "[closure][dam_break]") {
  const double e1 = dam_break_error(200), e2 = dam_break_error(400), e3 = dam_break_error(800);
  INFO("L1 errors / (h0 * 1 m): " << e1 << " " << e2 << " " << e3 << "; orders " << std::log2(e1 / e2) << " "
                                   << std::log2(e2 / e3));
  CHECK(e3 < 0.01);
  CHECK(std::log2(e1 / e2) > 0.5);
  CHECK(std::log2(e2 / e3) > 0.5);
}

TEST_CASE("closure: steady flow down an incline at the speed of the mu(I) law", "[closure][mu_of_I]") {
  // Uniform plug layer, tan θ between μ_s and μ_s + Δμ: u → I* a √(g_n a) / d with
  // I* = I₀ (tan θ − μ_s) / (μ_s + Δμ − tan θ) (F1).
  SectionSettings s = section(40, 400, 30, 20, INFINITY);
  s.friction.delta_mu = 0.26;
  s.friction.grain_diameter = 1e-3;
  const double theta = 25 * kDeg, h = 0.01;
  ShallowGranularFlow flow(s, tilted(theta), std::vector<double>(s.nx, h));
  flow.advance(15.0);  // relaxation time ≈ 1 s; the walls' disturbances have not reached x = 20 m
  const double mus = std::tan(20 * kDeg), gn = 9.81 * std::cos(theta);
  const double istar = 0.279 * (std::tan(theta) - mus) / (mus + 0.26 - std::tan(theta));
  const double expected = istar * h * std::sqrt(gn * h) / 1e-3;
  CHECK(flow.surface_speed()[200] == Approx(expected).epsilon(1e-4));
  CHECK(flow.depth()[200] == Approx(h).epsilon(1e-9));
}

TEST_CASE("closure: mass is conserved and depth stays non-negative in a sloshing bed", "[closure][conservation]") {
  // A deep bed and a thin one, rocked ±30° with period 6 s for 30 s.
  for (const double ell : {0.05, double(INFINITY)}) {
    SectionSettings s = section(2, 100, 26.7, 20, ell);
    s.friction.delta_mu = 0.2;
    std::vector<double> h(s.nx);
    for (int i = 0; i < s.nx; ++i) h[i] = i < 50 ? (ell < 1 ? 0.6 : 0.03) : 0.0;  // half the floor dry
    dem::PlatformTilt::Params p;
    p.amplitude = 30 * kDeg;
    p.frequency = 1.0 / 6;
    p.pause = 0;
    ShallowGranularFlow flow(s, ContainerGravity(std::make_shared<dem::PlatformTilt>(p), ContainerPlacement{}), h);
    const double v0 = flow.volume();
    double hmin = 1;
    flow.advance(30.0, [&](const ShallowGranularFlow& f) {
      hmin = std::min(hmin, *std::min_element(f.depth().begin(), f.depth().end()));
    });
    CAPTURE(ell);
    CHECK(std::abs(flow.volume() - v0) / v0 < 1e-13);
    CHECK(hmin >= 0.0);
    double moved = 0;
    for (int i = 0; i < s.nx; ++i) moved += std::abs(flow.depth()[i] - h[i]);
    CHECK(moved > 0.01 * v0 / flow.dx());  // it did move
  }
}
