// Invariants of the discrete model with every term on: total chaff is conserved to round-off, c
// stays in [0, 1] from a discontinuous start without clipping, and CVODE and SSP-RK3 agree.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "bed_fixture.hpp"
#include "continuum/integrator.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;

TEST_CASE("Total chaff is conserved to round-off over a long run", "[continuum][conservation]") {
  const std::string method = GENERATE(as<std::string>{}, "ssp_rk3", "cvode");
  Model model = full_bed(40, 10, Limiter::van_leer);
  std::vector<double> c = block(model.grid());
  const double m0 = model.chaff(c);
  IntegratorSettings s;
  s.method = method;
  auto integrator = make_integrator(s, model);
  double worst = 0;
  for (int j = 0; j < 20; ++j) {  // 20 × 30 s: about 15 turns of the convection cell
    integrator->advance(30.0 * j, 30.0 * (j + 1), c);
    worst = std::max(worst, std::abs(model.chaff(c) - m0) / m0);
  }
  INFO(method << ": " << integrator->stats().steps << " steps, worst relative change " << worst);
  REQUIRE(integrator->stats().steps > 100);
  REQUIRE(worst < 1e-12);
}

namespace {

struct BoundsCase {
  const char* limiter;
  double slope;      // ε of the surface h = H (1 + ε cos πx/L)
  bool diffusion;
  double tolerance;  // allowed excursion below 0 / above 1
};

}  // namespace

TEST_CASE("c stays in [0, 1] from a sharp front with limited reconstruction", "[continuum][bounds]") {
  // SSP-RK3 steps are convex combinations of forward-Euler steps that keep c in [0, 1] under the
  // rate bound (monotone fluxes, limited states). No value is ever clipped. The one exception is
  // diffusion on a sloping surface: its cross terms (diffusion_stencil.hpp, D1–D2) have weights of
  // both signs, so there the bound holds only to ~D σ h_x-sized excursions (measured ~4e-8 here).
  const BoundsCase k = GENERATE(BoundsCase{"van_leer", 0.0, true, 1e-14}, BoundsCase{"minmod", 0.0, true, 1e-14},
                                BoundsCase{"mc", 0.0, true, 1e-14}, BoundsCase{"van_leer", 0.2, false, 1e-14},
                                BoundsCase{"mc", 0.2, false, 1e-14}, BoundsCase{"van_leer", 0.2, true, 1e-6});
  Model model = full_bed(40, 12, limiter_from_name(k.limiter), 1e-3, k.diffusion ? 0.5 : 0.0, k.diffusion ? 1e-6 : 0.0,
                         k.slope);
  std::vector<double> c = block(model.grid());
  IntegratorSettings s;
  s.method = "ssp_rk3";
  auto integrator = make_integrator(s, model);
  double lo = 0, hi = 1;
  for (int j = 0; j < 40; ++j) {
    integrator->advance(5.0 * j, 5.0 * (j + 1), c);
    lo = std::min(lo, *std::min_element(c.begin(), c.end()));
    hi = std::max(hi, *std::max_element(c.begin(), c.end()));
  }
  INFO(k.limiter << ", slope " << k.slope << (k.diffusion ? ", with" : ", without") << " diffusion: min " << lo
                 << ", max " << hi);
  REQUIRE(lo >= -k.tolerance);
  REQUIRE(hi <= 1 + k.tolerance);
  // The chaff did move: the block has spread and risen.
  REQUIRE(*std::max_element(c.begin(), c.end()) < 0.999);
}

TEST_CASE("Without a limiter the same front over- and undershoots (the bound test can fail)", "[continuum][bounds]") {
  Model model = full_bed(40, 12, Limiter::unlimited);
  std::vector<double> c = block(model.grid());
  IntegratorSettings s;
  s.method = "ssp_rk3";
  auto integrator = make_integrator(s, model);
  integrator->advance(0, 20, c);
  const double lo = *std::min_element(c.begin(), c.end());
  INFO("min " << lo);
  REQUIRE(lo < -1e-3);
}

TEST_CASE("CVODE (BDF, band Jacobian) and SSP-RK3 agree", "[continuum][integrators]") {
  Model model = full_bed(32, 8, Limiter::van_leer);
  // A smooth start, so the comparison measures time integration, not the limiter's switching.
  std::vector<double> c0(model.size());
  const Grid& g = model.grid();
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) c0[g.index(i, k)] = 0.2 + 0.1 * std::cos(3.0 * g.x_centre(i) / 0.4) * (1 - g.sigma_centre(k));
  }
  IntegratorSettings a;
  a.method = "cvode";
  a.rtol = 1e-9;
  a.atol = 1e-12;
  IntegratorSettings b;
  b.method = "ssp_rk3";
  b.cfl = 0.2;
  auto ia = make_integrator(a, model);
  auto ib = make_integrator(b, model);
  std::vector<double> ca = c0, cb = c0;
  double diff = 0, change = 0;
  for (int j = 0; j < 4; ++j) {
    ia->advance(25.0 * j, 25.0 * (j + 1), ca);
    ib->advance(25.0 * j, 25.0 * (j + 1), cb);
    for (std::size_t m = 0; m < ca.size(); ++m) {
      diff = std::max(diff, std::abs(ca[m] - cb[m]));
      change = std::max(change, std::abs(ca[m] - c0[m]));
    }
  }
  INFO("max |c_cvode − c_ssp| = " << diff << " while c changed by up to " << change);
  REQUIRE(change > 0.02);
  REQUIRE(diff < 1e-6);
}
