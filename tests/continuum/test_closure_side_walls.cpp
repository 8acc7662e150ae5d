// Side-wall friction in the flow closure (continuum/closure/side_wall_friction.hpp, (W1)): a bed in a
// channel of width W is held exactly up to the tilt the implemented balance gives,
// tan θ = tan δ + μ_w h/W for a plug (tan(θ − β) = tan φ + μ_w a/W for a surface layer), flows above
// it at the rate and steady μ(I) speed that balance predicts, and without a width the closure is the
// 2-D one bit for bit.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "closure_fixture.hpp"
#include "dem/motion/platform_tilt.hpp"

using namespace grainscale::continuum::closure;
using namespace closure_test;

namespace {

SectionSettings channel(double length, int nx, double phi_deg, double delta_deg, double ell, double width, double mu_w) {
  SectionSettings s = section(length, nx, phi_deg, delta_deg, ell);
  s.friction.side_walls.width = width;
  s.friction.side_walls.friction = mu_w;
  return s;
}

double max_speed(const ShallowGranularFlow& f) {
  double m = 0;
  for (double u : f.surface_speed()) m = std::max(m, std::abs(u));
  return m;
}

}  // namespace

TEST_CASE("side walls: a plug in a channel is held up to tan(theta) = tan(delta) + mu_w h / W", "[closure][side_walls]") {
  // The default study's box: 30 mm wide, barley on perspex μ_w = 0.25, δ = 14°, a 10 mm plug.
  const double W = 0.03, mu_w = 0.25, h = 0.01;
  const double theta_c = std::atan(std::tan(14 * kDeg) + mu_w * h / W);  // 18.40°
  REQUIRE(theta_c / kDeg == Approx(18.40).margin(0.01));
  const SectionSettings s = channel(1, 40, 26.7, 14, INFINITY, W, mu_w);
  const std::vector<double> h0(s.nx, h);
  SECTION("held just below, 100 s: bit for bit at rest") {
    ShallowGranularFlow flow(s, tilted(theta_c - 1e-6), h0);
    flow.advance(100.0);
    CHECK(flow.depth() == h0);
    CHECK(max_speed(flow) == 0.0);
    CHECK(flow.steps() > 10);
  }
  SECTION("moves just above") {
    ShallowGranularFlow flow(s, tilted(theta_c + 1e-6), h0);
    flow.advance(1.0);
    CHECK(max_speed(flow) > 0.0);
  }
  SECTION("without the walls the same tilt is well past the floor's threshold") {
    SectionSettings open = s;
    open.friction.side_walls = SideWallFriction{};
    ShallowGranularFlow flow(open, tilted(theta_c - 1e-6), h0);
    flow.advance(0.5);
    CHECK(max_speed(flow) > 0.1);
  }
  SECTION("above it accelerates at g (sin theta - cos theta (tan delta + mu_w h / W))") {
    const double theta = theta_c + 0.5 * kDeg;
    ShallowGranularFlow flow(s, tilted(theta), h0);
    flow.advance(1.0);
    const double m = 9.81 * (std::sin(theta) - std::cos(theta) * (std::tan(14 * kDeg) + mu_w * h / W));
    // Away from the walls' influence the plug accelerates uniformly; the thinning near the upper wall
    // lowers μ_w h/W there, so the fastest face is a little ahead of m t.
    CHECK(flow.surface_speed()[s.nx / 2] == Approx(m * 1.0).epsilon(0.02));
  }
}

TEST_CASE("side walls: a deep bed's surface is held up to tan(theta - beta) = tan(phi) + mu_w l / W", "[closure][side_walls]") {
  // h ≫ ℓ: the flowing layer a(h) = ℓ (1 − e^{−h/ℓ}) = ℓ to e^{−60}.
  const double W = 0.2, mu_w = 0.3, ell = 0.04;
  const double surface_c = std::atan(std::tan(26.7 * kDeg) + mu_w * ell / W);  // 29.38° to the horizontal
  const SectionSettings s = channel(10, 50, 26.7, 14, ell, W, mu_w);
  const double theta = 20 * kDeg;
  for (const double off : {-0.02 * kDeg, +0.1 * kDeg}) {
    const double beta = -(surface_c + off - theta);  // surface slope relative to the floor
    std::vector<double> h(s.nx);
    for (int i = 0; i < s.nx; ++i) h[i] = 8.0 + std::tan(beta) * (i + 0.5) * s.length / s.nx;
    REQUIRE(*std::min_element(h.begin(), h.end()) > 60 * ell);
    ShallowGranularFlow flow(s, tilted(theta), h);
    flow.advance(off < 0 ? 100.0 : 1.0);
    CAPTURE(off / kDeg);
    if (off < 0) {
      CHECK(flow.depth() == h);
      CHECK(max_speed(flow) == 0.0);
    } else {
      CHECK(flow.surface_speed()[s.nx / 2] > 0.0);
    }
  }
}

TEST_CASE("side walls: steady flow in a channel at the speed of mu(I) + mu_w h / W", "[closure][side_walls][mu_of_I]") {
  // Uniform plug layer: tan θ = μ_s + μ_w h/W + Δμ I/(I₀ + I), so
  // I* = I₀ (tan θ − μ_s − μ_w h/W) / (μ_s + μ_w h/W + Δμ − tan θ) and u = I* h √(g_n h) / d.
  const double W = 0.1, mu_w = 0.3, h = 0.01;
  SectionSettings s = channel(40, 400, 30, 20, INFINITY, W, mu_w);
  s.friction.delta_mu = 0.26;
  s.friction.grain_diameter = 1e-3;
  const double theta = 26 * kDeg;
  ShallowGranularFlow flow(s, tilted(theta), std::vector<double>(s.nx, h));
  flow.advance(15.0);
  const double mu0 = std::tan(20 * kDeg) + mu_w * h / W, gn = 9.81 * std::cos(theta);
  const double istar = 0.279 * (std::tan(theta) - mu0) / (mu0 + 0.26 - std::tan(theta));
  REQUIRE(istar > 0);
  CHECK(flow.surface_speed()[200] == Approx(istar * h * std::sqrt(gn * h) / 1e-3).epsilon(1e-4));
  // Without the walls the same layer runs faster (a different I*): the term is what sets the speed.
  const double istar_open = 0.279 * (std::tan(theta) - std::tan(20 * kDeg)) / (std::tan(20 * kDeg) + 0.26 - std::tan(theta));
  CHECK(istar_open > 1.5 * istar);
}

TEST_CASE("side walls: without a width the closure is the 2-D one, bit for bit", "[closure][side_walls]") {
  // A sloshing bed (half the floor dry, μ(I) on, a surface layer) for 12 s: a section with no width but
  // a wall friction stated must give exactly the default friction's h and u at every step.
  dem::PlatformTilt::Params p;
  p.amplitude = 30 * kDeg;
  p.frequency = 1.0 / 6;
  p.pause = 0;
  const ContainerGravity g(std::make_shared<dem::PlatformTilt>(p), ContainerPlacement{});
  SectionSettings plain = channel(2, 100, 26.7, 20, 0.05, INFINITY, 0);
  plain.friction.side_walls = SideWallFriction{};  // the default: no walls
  plain.friction.delta_mu = 0.2;
  SectionSettings unset = plain;
  unset.friction.side_walls.friction = 0.4;  // no width: ignored
  SectionSettings zero = plain;
  zero.friction.side_walls = {0.05, 0.0};  // walls without friction
  std::vector<double> h(plain.nx);
  for (int i = 0; i < plain.nx; ++i) h[i] = i < 50 ? 0.6 : 0.0;
  ShallowGranularFlow a(plain, g, h), b(unset, g, h), c(zero, g, h);
  bool same = true;
  for (int k = 0; k < 40; ++k) {
    const double t = 0.3 * (k + 1);
    a.advance(t), b.advance(t), c.advance(t);
    same = same && a.depth() == b.depth() && a.surface_speed() == b.surface_speed() && a.steps() == b.steps();
    same = same && a.depth() == c.depth() && a.surface_speed() == c.surface_speed();
  }
  CHECK(same);
  CHECK(a.steps() > 100);
  CHECK(a.depth() != h);  // it flowed
  // And a width with friction does change it.
  SectionSettings walls = plain;
  walls.friction.side_walls = {0.05, 0.4};
  ShallowGranularFlow d(walls, g, h);
  d.advance(12.0);
  CHECK(d.depth() != a.depth());
}
