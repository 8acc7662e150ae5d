// Segregation: the face flux's properties, the closed-form steady profile in a uniform shear layer,
// and the full model (advection + segregation + shear and background diffusion) against a
// manufactured solution on a sloping bed.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>

#include "continuum/analytic_flows.hpp"
#include "continuum/integrator.hpp"
#include "continuum/model.hpp"
#include "continuum/terms/advection.hpp"
#include "continuum/terms/background_diffusion.hpp"
#include "continuum/terms/segregation.hpp"
#include "continuum/terms/shear_diffusion.hpp"
#include "convergence_table.hpp"
#include "manufactured.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;
constexpr double pi = std::numbers::pi;

TEST_CASE("The Engquist-Osher segregation flux is consistent and monotone", "[continuum][segregation]") {
  const double w = GENERATE(2.0, -1.5);
  for (int a = 0; a <= 20; ++a) {
    const double ca = a / 20.0;
    CHECK(segregation_face_flux(w, ca, ca) == Approx(w * ca * (1 - ca)).margin(1e-15));
    for (int b = 0; b < 20; ++b) {
      const double cb = b / 20.0, db = 0.05;
      // Non-decreasing in the state below the face, non-increasing in the state above.
      CHECK(segregation_face_flux(w, cb + db, ca) >= segregation_face_flux(w, cb, ca) - 1e-15);
      CHECK(segregation_face_flux(w, ca, cb + db) <= segregation_face_flux(w, ca, cb) + 1e-15);
    }
  }
  // No chaff or only chaff: nothing to segregate.
  CHECK(segregation_face_flux(w, 0, 0) == 0);
  CHECK(segregation_face_flux(w, 1, 1) == 0);
}

namespace {

/// Closed form for constant w_s and D: w_s c(1−c) = D dc/dz ⇒ c = 1 / (1 + exp(−λ(z − z0))),
/// λ = w_s / D, with z0 such that ∫₀ᴴ c dz = c̄ H: ∫ c dz = ln((1 + e^{λ(H−z0)}) / (1 + e^{−λ z0})) / λ.
double logistic_z0(double lambda, double H, double mean) {
  auto content = [&](double z0) {
    return (std::log1p(std::exp(lambda * (H - z0))) - std::log1p(std::exp(-lambda * z0))) / lambda;
  };
  double lo = -10 * H, hi = 10 * H;  // content decreases as z0 rises
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (content(mid) > mean * H ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST_CASE("Steady segregation-diffusion in a uniform shear layer is the logistic profile", "[continuum][segregation]") {
  // S γ̇ = 1 mm/s against D = C γ̇ d² + D0 = 2e-5 m²/s in a 0.1 m layer: Péclet λH = 5.
  const double H = 0.1, rate = 2.0, S = 5e-4, C = 0.5, d = 4e-3, mean = 0.3;
  const double D0 = 2e-5 - C * rate * d * d;
  const double lambda = S * rate / (C * rate * d * d + D0);
  const double z0 = logistic_z0(lambda, H, mean);
  const Field exact = [&](double, double z, double) { return 1 / (1 + std::exp(-lambda * (z - z0))); };
  ConvergenceTable table("steady logistic profile, λH = " + std::to_string(lambda * H));
  double max_error = 0;
  for (int nz : {50, 100, 200}) {
    Model model(Grid::flat(0.05, H, 2, nz), std::make_shared<UniformShear>(rate));
    model.add_term(std::make_unique<Segregation>(S, Limiter::van_leer));
    model.add_term(std::make_unique<ShearDiffusion>(C, d));
    model.add_term(std::make_unique<BackgroundDiffusion>(D0));
    std::vector<double> c(model.size(), mean);
    IntegratorSettings s;
    s.rtol = 1e-10;
    s.atol = 1e-13;
    auto integrator = make_integrator(s, model);
    integrator->advance(0, 20 * H * H / 2e-5, c);  // 20 diffusion times: transients decay as e^{−20π²}
    table.add(nz, l2_error(model.grid(), c, exact, 0));
    max_error = 0;
    for (int k = 0; k < nz; ++k) {
      max_error = std::max(max_error, std::abs(c[model.grid().index(0, k)] - exact(0, model.grid().z_centre(0, k), 0)));
    }
    CHECK(model.chaff(c) == Approx(mean * 0.05 * H).epsilon(1e-12));
  }
  INFO(table.str() << "max error at nz = 200: " << max_error);
  REQUIRE(max_error < 1e-3);
  REQUIRE(table.last_rate() > 2 - 0.1);
}

TEST_CASE("The full model converges at second order to a manufactured solution on a sloping bed",
          "[continuum][segregation]") {
  // All four terms at once. γ̇ vanishes on the floor and the surface, and c has zero normal
  // derivative on every boundary, so c_exact satisfies the no-flux conditions of the model. c_exact
  // stays in [0.2, 0.8]: the limiters use the bounds [0, 1] at boundary cells (reconstruction.cpp).
  const double L = 0.4, H = 0.1, A = 5e-4, S = 2e-3, C = 2.0, d = 4e-3, D0 = 2e-5, T = 1.0;
  auto h = [&](double x) { return H * (1 + 0.25 * std::cos(pi * x / L)); };
  const Field psi = [&](double x, double z, double) { return A * std::sin(pi * x / L) * std::sin(pi * z / h(x)); };
  const Field shear = [&](double x, double z, double) {
    return 2.0 * std::sin(pi * z / h(x)) * (1 + 0.5 * std::sin(pi * x / L));
  };
  const Field exact = [&](double x, double z, double t) {
    return 0.5 + 0.1 * (1 + 0.5 * std::sin(t)) * std::cos(pi * x / L) * (std::cos(pi * z / h(x)) + 1);
  };
  const Manufactured mms{exact, psi, shear, S, C * d * d, D0};
  const std::string limiter = GENERATE(as<std::string>{}, "van_leer", "unlimited");
  ConvergenceTable table("manufactured full model, " + limiter);
  for (int n : {16, 32, 64}) {
    Model model(terrain_grid(L, 2 * n, n / 2, h), std::make_shared<FunctionFlow>(psi, shear, true));
    model.add_term(std::make_unique<Advection>(limiter_from_name(limiter)));
    model.add_term(std::make_unique<Segregation>(S, limiter_from_name(limiter)));
    model.add_term(std::make_unique<ShearDiffusion>(C, d));
    model.add_term(std::make_unique<BackgroundDiffusion>(D0));
    model.set_source([&](double x, double z, double t) { return mms.source(x, z, t); });
    std::vector<double> c = sample(model.grid(), exact, 0);
    IntegratorSettings s;
    s.rtol = 1e-9;
    s.atol = 1e-12;
    auto integrator = make_integrator(s, model);
    integrator->advance(0, T, c);
    table.add(n, l2_error(model.grid(), c, exact, T));
  }
  INFO(table.str());
  REQUIRE(table.last_rate() > 2 - 0.1);
}
