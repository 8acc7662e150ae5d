// Advection by a convection cell in a bed with a sloping surface: a manufactured, time-dependent
// solution must converge at second order in space with the unlimited (Fromm) reconstruction and,
// on data without interior extrema, with the limited ones (van Leer, minmod, MC); the donor-cell
// scheme at first order. At smooth extrema every TVD limiter cuts the slope to zero (first order in
// a few cells), so on data with extrema the limited scheme is only asked for order > 1.5.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>

#include "continuum/analytic_flows.hpp"
#include "continuum/integrator.hpp"
#include "continuum/model.hpp"
#include "continuum/terms/advection.hpp"
#include "convergence_table.hpp"
#include "manufactured.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;
constexpr double pi = std::numbers::pi;

namespace {

struct Case {
  const char* limiter;
  bool extrema;  // exact solution with interior extrema (else monotone in x and z)
  double order;  // required: rate > order − 0.1
};

}  // namespace

TEST_CASE("Manufactured advection by a convection cell converges at the scheme's order", "[continuum][advection]") {
  const Case k = GENERATE(Case{"unlimited", true, 2}, Case{"van_leer", false, 2}, Case{"minmod", false, 2},
                          Case{"mc", false, 2}, Case{"van_leer", true, 1.6}, Case{"first_order", true, 1});
  const double L = 0.4, H = 0.1, A = 1e-3, T = 1.0;  // |u| up to ~3 cm/s
  auto h = [&](double x) { return H * (1 + 0.25 * std::cos(pi * x / L)); };
  const Field psi = [&](double x, double z, double) { return A * std::sin(pi * x / L) * std::sin(pi * z / h(x)); };
  const Field no_shear = [](double, double, double) { return 0.0; };
  // Smooth and time-dependent; with interior extrema (where limiters cut slopes) or monotone.
  const Field with_extrema = [&](double x, double z, double t) {
    return 0.5 + 0.3 * std::cos(pi * x / L - 0.2 * t) * std::sin(pi * z / H + 0.3);
  };
  const Field monotone = [&](double x, double z, double t) {
    return 0.45 + 0.2 * std::tanh(2 * (x / L - 0.5) + 0.3 * std::sin(t)) + 0.1 * (z / H) * (z / H);
  };
  const Field exact = k.extrema ? with_extrema : monotone;
  const Manufactured mms{exact, psi, no_shear};
  ConvergenceTable table(std::string("manufactured advection, ") + k.limiter +
                         (k.extrema ? ", data with extrema" : ", monotone data"));
  for (int n : {16, 32, 64}) {
    Model model(terrain_grid(L, 2 * n, n / 2, h), std::make_shared<FunctionFlow>(psi, no_shear, true));
    model.add_term(std::make_unique<Advection>(limiter_from_name(k.limiter)));
    model.set_source([&](double x, double z, double t) { return mms.source(x, z, t); });
    std::vector<double> c = sample(model.grid(), exact, 0);
    IntegratorSettings s;
    s.method = "ssp_rk3";
    s.cfl = 0.4;
    auto integrator = make_integrator(s, model);
    integrator->advance(0, T, c);
    table.add(n, l2_error(model.grid(), c, exact, T));
  }
  INFO(table.str());
  REQUIRE(table.last_rate() > k.order - 0.1);
}
