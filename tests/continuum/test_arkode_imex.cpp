// ARKODE IMEX (arkode_integrator.hpp): diffusion implicit, advection and segregation explicit. It
// keeps the total chaff to round-off (fixed and moving surface), agrees with CVODE, and on a finely
// resolved column, where diffusion is stiff, takes far fewer steps than the explicit SSP-RK3.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bed_fixture.hpp"
#include "continuum/integrator.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;

TEST_CASE("ARKODE IMEX keeps chaff to round-off and agrees with CVODE", "[continuum][integrators][imex]") {
  Model model = full_bed(32, 8, Limiter::van_leer);
  const Grid& g = model.grid();
  std::vector<double> c0(model.size());
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) c0[g.index(i, k)] = 0.2 + 0.1 * std::cos(3.0 * g.x_centre(i) / 0.4) * (1 - g.sigma_centre(k));
  }
  IntegratorSettings a;
  a.method = "arkode_imex";
  a.rtol = 1e-9;
  a.atol = 1e-12;
  IntegratorSettings b = a;
  b.method = "cvode";
  auto ia = make_integrator(a, model);
  auto ib = make_integrator(b, model);
  REQUIRE(ia->name() == "arkode_imex");
  std::vector<double> ca = c0, cb = c0;
  const double m0 = model.chaff(c0);
  double diff = 0, drift = 0;
  for (int j = 0; j < 4; ++j) {
    ia->advance(25.0 * j, 25.0 * (j + 1), ca);
    ib->advance(25.0 * j, 25.0 * (j + 1), cb);
    drift = std::max(drift, std::abs(model.chaff(ca) - m0) / m0);
    for (std::size_t m = 0; m < ca.size(); ++m) diff = std::max(diff, std::abs(ca[m] - cb[m]));
  }
  INFO("IMEX " << ia->stats().steps << " steps, max |c_imex - c_cvode| = " << diff << ", chaff drift " << drift);
  CHECK(diff < 1e-6);
  CHECK(drift < 1e-12);
}

TEST_CASE("ARKODE IMEX on a moving surface: chaff to round-off, a uniform c stays uniform", "[continuum][integrators][imex][moving]") {
  SloshingFlow::Shape shape;
  shape.amplitude = 0.015;
  shape.cell = 3e-4;
  shape.background_shear = 0.05;
  auto flow = std::make_shared<SloshingFlow>(shape);
  Model model(Grid::flat(0.4, 0.1, 24, 8), flow);
  model.add_term(std::make_unique<Advection>(Limiter::van_leer));
  model.add_term(std::make_unique<ShearDiffusion>(0.5, 4e-3));
  model.add_term(std::make_unique<BackgroundDiffusion>(1e-6));
  IntegratorSettings s;
  s.method = "arkode_imex";
  auto integrator = make_integrator(s, model);
  std::vector<double> uniform = model.state(0, std::vector<double>(model.size(), 0.3));
  integrator->advance(0, 4.0, uniform);
  double worst = 0;
  for (double c : model.concentration(4.0, uniform)) worst = std::max(worst, std::abs(c - 0.3));
  model.add_term(std::make_unique<Segregation>(1e-3, Limiter::van_leer));
  auto again = make_integrator(s, model);
  std::vector<double> y = model.state(0, block(model.grid()));
  const double m0 = model.state_chaff(y);
  again->advance(0, 4.0, y);
  const double drift = std::abs(model.state_chaff(y) - m0) / m0;
  INFO("max |c - 0.3| = " << worst << ", chaff drift " << drift);
  CHECK(worst < 1e-12);
  CHECK(drift < 1e-12);
}

TEST_CASE("ARKODE IMEX steps over the diffusive limit of a fine column", "[continuum][integrators][imex]") {
  // 64 layers in 0.1 m: D/dz² ≈ 4 /s limits SSP-RK3 to dt ≈ 0.05 s; IMEX follows the slow dynamics.
  Model model = full_bed(8, 64, Limiter::van_leer, 1e-3, 0.5, 1e-5, 0.0);
  std::vector<double> c0 = block(model.grid());
  IntegratorSettings imex;
  imex.method = "arkode_imex";
  IntegratorSettings ssp;
  ssp.method = "ssp_rk3";
  auto ii = make_integrator(imex, model);
  auto is = make_integrator(ssp, model);
  std::vector<double> ci = c0, cs = c0;
  ii->advance(0, 100, ci);
  is->advance(0, 100, cs);
  double diff = 0;
  for (std::size_t m = 0; m < ci.size(); ++m) diff = std::max(diff, std::abs(ci[m] - cs[m]));
  std::printf("fine column, 100 s: arkode_imex %ld steps, ssp_rk3 %ld steps, max difference %.2g\n", ii->stats().steps,
              is->stats().steps, diff);
  INFO("arkode_imex " << ii->stats().steps << " steps, ssp_rk3 " << is->stats().steps << ", max difference " << diff);
  CHECK(ii->stats().steps * 4 < is->stats().steps);  // measured 632 against 3692
  CHECK(diff < 1e-3);
}
