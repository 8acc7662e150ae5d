// The candidate effects of `grainscale loop` (continuum/terms/: lever arm, surface drift,
// concentration-dependent segregation, clustering diffusion, wall mobility, pause creep): each one's
// steady balance against diffusion in a uniform shear layer is its closed-form profile (zero net
// flux: drift q c(1 − c) = D ∇c, integrated analytically), and all of them together conserve chaff
// and keep c in [0, 1] on a sloping bed with a convection cell.
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>

#include "continuum/analytic_flows.hpp"
#include "continuum/drift_flux.hpp"
#include "continuum/integrator.hpp"
#include "continuum/model.hpp"
#include "continuum/simulate.hpp"
#include "continuum/term_registry.hpp"
#include "continuum/terms/background_diffusion.hpp"
#include "continuum/terms/lever_arm.hpp"
#include "bed_fixture.hpp"

using namespace grainscale;
using namespace grainscale::continuum;
constexpr double pi = std::numbers::pi;

namespace {

/// A term from the registry with the given parameters (the way a YAML file or the loop builds it).
std::unique_ptr<FluxTerm> term(const std::string& name, const std::string& yaml) {
  YamlMap m(YAML::Load(yaml), "test", "terms." + name);
  return make_term(name, m);
}

/// Integrate to steady state (CVODE, tight tolerances) from a uniform `mean`.
std::vector<double> steady(const Model& model, double mean, double t_end) {
  std::vector<double> c(model.size(), mean);
  IntegratorSettings s;
  s.rtol = 1e-10;
  s.atol = 1e-13;
  make_integrator(s, model)->advance(0, t_end, c);
  return c;
}

/// Largest |c − exact(x, z; b)| with b chosen (bisection, exact increasing in b) so the exact field
/// holds the same chaff as the numerical one.
double max_error(const Model& model, const std::vector<double>& c, const std::function<double(double, double, double)>& exact,
                 double b_lo, double b_hi) {
  const Grid& g = model.grid();
  auto content = [&](double b) {
    double sum = 0;
    for (int i = 0; i < g.nx(); ++i)
      for (int k = 0; k < g.nz(); ++k) sum += g.area(i, k) * exact(g.x_centre(i), g.z_centre(i, k), b);
    return sum;
  };
  const double target = model.chaff(c);
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (b_lo + b_hi);
    (content(mid) < target ? b_lo : b_hi) = mid;
  }
  const double b = 0.5 * (b_lo + b_hi);
  double err = 0;
  for (int i = 0; i < g.nx(); ++i)
    for (int k = 0; k < g.nz(); ++k) err = std::max(err, std::abs(c[g.index(i, k)] - exact(g.x_centre(i), g.z_centre(i, k), b)));
  return err;
}

double logistic(double v) { return 1 / (1 + std::exp(-v)); }

}  // namespace

TEST_CASE("The drift face flux is consistent and monotone for both mobilities", "[continuum][loop]") {
  for (Mobility m : {Mobility::symmetric, Mobility::dilute}) {
    for (double q : {1.5, -0.7}) {
      for (int a = 0; a <= 20; ++a) {
        const double ca = a / 20.0;
        CHECK(drift_face_flux(m, q, ca, ca) == Approx(q * mobility(m, ca)).margin(1e-15));
        for (int b = 0; b < 20; ++b) {
          const double cb = b / 20.0;
          CHECK(drift_face_flux(m, q, cb + 0.05, ca) >= drift_face_flux(m, q, cb, ca) - 1e-15);
          CHECK(drift_face_flux(m, q, ca, cb + 0.05) <= drift_face_flux(m, q, ca, cb) + 1e-15);
        }
      }
      CHECK(drift_face_flux(m, q, 0, 0) == 0);
      CHECK(drift_face_flux(m, q, 1, 1) == 0);
    }
  }
}

TEST_CASE("Lever arm: the steady profile is logit c = -(k/D) |r - a|^2 / 2 + b", "[continuum][loop]") {
  // k = S γ̇ <ω²> / g = 0.01 * 1 * 0.1 / 9.81; D = 1e-5: logit c changes by about 3 along the bed.
  const double S = 0.01, omega2 = 0.1, ax = -0.6, az = -0.3, D = 1e-5, k = S * 1.0 * omega2 / 9.81;
  Model model(Grid::flat(0.4, 0.1, 40, 10), std::make_shared<UniformShear>(1.0));
  model.add_term(term("lever_arm", "{S: 0.01, omega2: 0.1, axis_x: -0.6, axis_z: -0.3}"));
  model.add_term(std::make_unique<BackgroundDiffusion>(D));
  const auto c = steady(model, 0.3, 20 * 0.16 / D);
  const double err = max_error(
      model, c, [&](double x, double z, double b) { return logistic(-k / D * ((x - ax) * (x - ax) + (z - az) * (z - az)) / 2 + b); },
      -50, 50);
  INFO("max error " << err);
  CHECK(err < 2e-3);
  CHECK(c[model.grid().index(0, 0)] > c[model.grid().index(39, 0)] + 0.3);  // chaff gathers towards the axis (x < 0)
  // A whole-bed mobility rate replaces the local shear rate; with ⟨α²⟩ the drift follows (G2)–(G3).
  const auto whole = term("lever_arm", "{S: 0.01, omega2: 0.1, axis_x: -0.6, axis_z: -0.3, rate: 3.0}");
  const auto& lever = dynamic_cast<const LeverArm&>(*whole);
  CHECK(lever.drift(0.1, 0.05, 0.2).first == Approx(-S * 3.0 * omega2 * 0.7 / 9.81).epsilon(1e-12));
  const auto swung = term("lever_arm", "{S: 0.01, omega2: 1.84, alpha2: 18.2, axis_x: -0.8, axis_z: 0.0}");
  const auto [lean_x, lean_z] = effective_gravity_anomaly({1.84, 18.2, -0.8, 0.0, 0.0}, 0.1, 0.02);
  CHECK(dynamic_cast<const LeverArm&>(*swung).drift(0.1, 0.02, 0.5).first == Approx(-0.01 * 0.5 * lean_x).epsilon(1e-12));
  CHECK(dynamic_cast<const LeverArm&>(*swung).drift(0.1, 0.02, 0.5).second == Approx(-0.01 * 0.5 * lean_z).epsilon(1e-12));
  CHECK(lean_x < 0);  // the swing leans the bed towards the axis: chaff drifts away from it
}

TEST_CASE("Surface drift through the whole depth: logit c = -(U L / (pi D)) cos(pi (x/L - 1/2)) + b", "[continuum][loop]") {
  const double U = 2e-4, L = 0.4, D = 1e-5;
  Model model(Grid::flat(L, 0.05, 80, 2), std::make_shared<UniformShear>(1.0));
  model.add_term(term("surface_drift", "{U: 2.0e-4, thickness: 0.06}"));  // layer thicker than the bed
  model.add_term(std::make_unique<BackgroundDiffusion>(D));
  const auto c = steady(model, 0.2, 20 * L * L / D);
  const double err = max_error(
      model, c, [&](double x, double, double b) { return logistic(-U * L / (pi * D) * std::cos(pi * (x / L - 0.5)) + b); }, -50, 50);
  INFO("max error " << err);
  CHECK(err < 2e-3);
  // Only the top layer drifts when the layer is thinner than the bed.
  Model thin(Grid::flat(L, 0.05, 8, 5), std::make_shared<UniformShear>(1.0));
  thin.add_term(term("surface_drift", "{U: 2.0e-4, thickness: 0.01}"));
  const std::vector<double> uniform(thin.size(), 0.3);
  FaceFluxes f;
  thin.face_fluxes(0, uniform, f);
  CHECK(f.x[x_face(thin.grid(), 6, 4)] > 0);    // top layer, right half: towards the right end
  CHECK(f.x[x_face(thin.grid(), 2, 4)] < 0);    // top layer, left half: towards the left end
  CHECK(std::abs(f.x[x_face(thin.grid(), 6, 3)]) < 1e-12 * f.x[x_face(thin.grid(), 6, 4)]);  // below the layer (round-off)
}

TEST_CASE("Concentration-dependent segregation: ln(c/(1-c)) + 1/(1-c) = lambda z + b", "[continuum][loop]") {
  const double S = 5e-4, rate = 2.0, D = 5e-5, H = 0.1;  // lambda H = S rate H / D = 2
  const double lambda = S * rate / D;
  Model model(Grid::flat(0.04, H, 2, 100), std::make_shared<UniformShear>(rate));
  model.add_term(term("concentration_segregation", "{S: 5.0e-4}"));
  model.add_term(std::make_unique<BackgroundDiffusion>(D));
  const auto c = steady(model, 0.3, 20 * H * H / D);
  // G(c) is increasing: invert it by bisection for the exact profile.
  auto exact = [&](double, double z, double b) {
    const double target = lambda * z + b;
    double lo = 1e-12, hi = 1 - 1e-12;
    for (int it = 0; it < 100; ++it) {
      const double mid = 0.5 * (lo + hi);
      (std::log(mid / (1 - mid)) + 1 / (1 - mid) < target ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  const double err = max_error(model, c, exact, -30, 30);
  INFO("max error " << err << ", lambda H = " << lambda * H);
  CHECK(err < 1e-3);
  CHECK(c.back() > c.front());
}

TEST_CASE("Wall mobility decays away from the wall: logit c = W exp(-d / l) z / D + b", "[continuum][loop]") {
  const double W = 1e-4, ell = 0.01, D = 1e-5, H = 0.05;
  for (const double L : {0.04, 0.12}) {  // two columns, their centres L/4 from a wall
    Model model(Grid::flat(L, H, 2, 100), std::make_shared<UniformShear>(1.0));
    model.add_term(term("wall_mobility", "{W: 1.0e-4, length: 0.01}"));
    model.add_term(std::make_unique<BackgroundDiffusion>(D));
    const auto c = steady(model, 0.3, 20 * H * H / D);
    const double v = W * std::exp(-L / 4 / ell);
    const double err = max_error(model, c, [&](double, double z, double b) { return logistic(v * z / D + b); }, -50, 50);
    INFO("L = " << L << ": max error " << err);
    CHECK(err < 1e-3);
  }
}

TEST_CASE("Pause creep against clustering diffusion: c = 1 - (1 - c0) exp(-f V z / (C rate d^2))", "[continuum][loop]") {
  // Zero flux: f V c (1 − c) = C γ̇ d² c dc/dz  =>  dc/dz = (f V / K)(1 − c).
  const double V = 1e-4, fp = 0.5, C = 0.5, rate = 2.0, d = 4e-3, H = 0.05;
  const double K = C * rate * d * d, lambda = fp * V / K;  // lambda H = 3.1
  Model model(Grid::flat(0.04, H, 2, 100), std::make_shared<UniformShear>(rate));
  model.add_term(term("pause_creep", "{V: 1.0e-4, pause_fraction: 0.5}"));
  model.add_term(term("clustering_diffusion", "{C: 0.5, d: 4.0e-3}"));
  const auto c = steady(model, 0.7, 40 * H * H / K);
  const double err = max_error(model, c, [&](double, double z, double c0) { return 1 - (1 - c0) * std::exp(-lambda * z); }, -5, 1);
  INFO("max error " << err << ", lambda H = " << lambda * H);
  CHECK(err < 2e-3);
}

TEST_CASE("All candidate terms together conserve chaff and keep c in [0, 1] on a sloping bed", "[continuum][loop]") {
  Model model = test::full_bed(16, 8, Limiter::van_leer);
  model.add_term(term("lever_arm", "{S: 0.01, omega2: 0.5, axis_x: -1.0, axis_z: -0.3}"));
  model.add_term(term("surface_drift", "{U: 1.0e-4, thickness: 0.02}"));
  model.add_term(term("concentration_segregation", "{S: 1.0e-3}"));
  model.add_term(term("clustering_diffusion", "{C: 0.5}"));
  model.add_term(term("wall_mobility", "{W: 1.0e-4}"));
  model.add_term(term("pause_creep", "{V: 1.0e-5}"));
  std::vector<double> c0 = test::block(model.grid());
  IntegratorSettings s{"ssp_rk3"};
  const auto out = simulate(model, c0, 0, {100, 400}, s);
  for (const auto& c : out) {
    CHECK(model.chaff(c) == Approx(model.chaff(c0)).epsilon(1e-12));
    CHECK(*std::min_element(c.begin(), c.end()) >= -1e-9);
    CHECK(*std::max_element(c.begin(), c.end()) <= 1 + 1e-9);
  }
  // Every candidate is registered with the parameters the loop fits.
  int candidates = 0;
  for (const auto& e : term_registry()) candidates += !e.candidate_parameters.empty();
  CHECK(candidates == 6);
}

TEST_CASE("Lever arm in a surface layer: the drift acts in the top delta only (L2)", "[continuum][loop][lever_arm]") {
  // A flat 0.1 m bed in 10 cells; the layer's bottom (0.065 m) halves cell 6. With a uniform c the
  // flux through a face is q c (1 − c), so it scales with the face's part in the layer.
  const std::string lean = "S: 0.01, omega2: 0.1, axis_x: -0.6, axis_z: -0.3";
  auto fluxes = [&](const std::string& extra) {
    Model model(Grid::flat(0.4, 0.1, 8, 10), std::make_shared<UniformShear>(1.0));
    model.add_term(term("lever_arm", "{" + lean + extra + "}"));
    const std::vector<double> uniform(model.size(), 0.3);
    FaceFluxes f;
    model.face_fluxes(0, uniform, f);
    return f;
  };
  const FaceFluxes whole = fluxes(""), layer = fluxes(", layer: 0.035"), deep = fluxes(", layer: 0.2");
  const Grid g = Grid::flat(0.4, 0.1, 8, 10);
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const std::size_t face = x_face(g, f, k);
      INFO("x-face " << f << ", cell " << k);
      REQUIRE(whole.x[face] < 0);  // light chaff against the centrifugal lean: towards the axis at x = -0.6
      const double part = k >= 7 ? 1.0 : k == 6 ? 0.5 : 0.0;
      CHECK(layer.x[face] == Approx(part * whole.x[face]).epsilon(1e-9).margin(1e-20));
      CHECK(deep.x[face] == Approx(whole.x[face]).epsilon(1e-12));  // a layer deeper than the bed: (L1)
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const std::size_t face = s_face(g, i, m);
      INFO("column " << i << ", sigma-face " << m);
      CHECK(layer.s[face] == Approx(m >= 7 ? whole.s[face] : 0.0).margin(1e-12 * std::abs(whole.s[face])));
      CHECK(deep.s[face] == whole.s[face]);
    }
  }
}
