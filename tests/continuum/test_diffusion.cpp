// Diffusion on the terrain-following grid: an analytic decaying mode on a flat bed, and a
// manufactured solution on a bed with a sloping free surface (exercises the cross terms D1, D2 of
// diffusion_stencil.hpp). Both must converge at second order.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>

#include "continuum/analytic_flows.hpp"
#include "continuum/integrator.hpp"
#include "continuum/model.hpp"
#include "continuum/terms/background_diffusion.hpp"
#include "continuum/terms/shear_diffusion.hpp"
#include "convergence_table.hpp"
#include "manufactured.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;
constexpr double pi = std::numbers::pi;

TEST_CASE("A cosine mode decays at the analytic rate, second order in space", "[continuum][diffusion]") {
  // c = ½ + ¼ cos(πx/L) cos(πz/H) e^{−λt}, λ = D π² (1/L² + 1/H²): zero flux on all four sides.
  const double L = 0.4, H = 0.1, D = 2e-4, T = 2.0;
  const double lambda = D * pi * pi * (1 / (L * L) + 1 / (H * H));
  const Field exact = [&](double x, double z, double t) {
    return 0.5 + 0.25 * std::cos(pi * x / L) * std::cos(pi * z / H) * std::exp(-lambda * t);
  };
  const std::string method = GENERATE(as<std::string>{}, "cvode", "ssp_rk3");
  ConvergenceTable table{"cosine mode, flat bed, " + method};
  for (int n : {8, 16, 32}) {
    Model model(Grid::flat(L, H, 2 * n, n / 2), std::make_shared<UniformShear>(0.0));
    model.add_term(std::make_unique<BackgroundDiffusion>(D));
    std::vector<double> c = sample(model.grid(), exact, 0);
    IntegratorSettings s;
    s.method = method;
    s.rtol = 1e-10;
    s.atol = 1e-12;
    auto integrator = make_integrator(s, model);
    integrator->advance(0, T, c);
    table.add(n, l2_error(model.grid(), c, exact, T));
  }
  INFO(table.str());
  REQUIRE(table.last_rate() > 2 - 0.1);
  REQUIRE(table.error.back() < 1e-3);
}

TEST_CASE("Manufactured diffusion on a sloping bed converges at second order", "[continuum][diffusion]") {
  // Bed surface h(x) = H (1 + ε cos(πx/L)): flat at the walls, sloping in between. The exact
  // solution c = ½ + a T(t) cos(πx/L) (cos πσ + 1), σ = z/h, has zero normal derivative on the floor,
  // walls and the sloping surface, so it satisfies the model's no-flux boundaries exactly.
  const double L = 0.4, H = 0.1, eps = GENERATE(0.0, 0.25);
  auto h = [&](double x) { return H * (1 + eps * std::cos(pi * x / L)); };
  const Field exact = [&](double x, double z, double t) {
    return 0.5 + 0.1 * (1 + 0.5 * std::sin(t)) * std::cos(pi * x / L) * (std::cos(pi * z / h(x)) + 1);
  };
  // Shear-rate-dependent D = K γ̇ + D0 with a smooth, non-uniform γ̇: D varies across faces.
  const Field shear = [&](double x, double z, double) { return 1.0 + 0.5 * std::sin(pi * x / L) * z / H; };
  const double d = 4e-3, C = 6.0, D0 = 5e-5, T = 1.0;  // K = C d² ≈ 1e-4 m²
  Manufactured mms{exact, nullptr, shear, 0.0, C * d * d, D0};
  ConvergenceTable table{"manufactured diffusion, slope ε = " + std::to_string(eps)};
  for (int n : {8, 16, 32}) {
    Model model(terrain_grid(L, 2 * n, n / 2, h), std::make_shared<FunctionFlow>(
                                                     [](double, double, double) { return 0.0; }, shear, true));
    model.add_term(std::make_unique<ShearDiffusion>(C, d));
    model.add_term(std::make_unique<BackgroundDiffusion>(D0));
    model.set_source([&](double x, double z, double t) { return mms.source(x, z, t); });
    std::vector<double> c = sample(model.grid(), exact, 0);
    IntegratorSettings s;
    s.method = "cvode";
    s.rtol = 1e-10;
    s.atol = 1e-12;
    auto integrator = make_integrator(s, model);
    integrator->advance(0, T, c);
    table.add(n, l2_error(model.grid(), c, exact, T));
  }
  INFO(table.str());
  REQUIRE(table.last_rate() > 2 - 0.1);
}
