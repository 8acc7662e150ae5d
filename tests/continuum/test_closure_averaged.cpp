// The cycle-averaged slow-time model (continuum/closure/cycle_averaged_transport.hpp): the fit of
// (A1) F̄ = V (c_L + c_R)/2 − K (c_R − c_L) to cycle means, K left unfitted where the difference
// across a face is unresolved, and the model integrated implicitly (CVODE BDF, as hold_run.cpp
// does) against its exact discrete steady profile.
//
// Steady state of (A1) with closed ends: every face flux vanishes, so
//   c_{i+1} / c_i = (K + V/2) / (K − V/2) = r                                               (S1)
// a geometric profile (the discrete form of c ∝ exp(V x / K dx)), scaled to the conserved total.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "continuum/analytic_flows.hpp"
#include "continuum/closure/cycle_averaged_transport.hpp"
#include "continuum/face_coefficients.hpp"
#include "continuum/integrator.hpp"
#include "continuum/model.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::closure;

namespace {

/// A 1-D row of nx cells (nz = 1) with the same V and K on every interior x-face.
std::unique_ptr<Model> uniform_row(int nx, double V, double K) {
  const Grid g = Grid::flat(1.0, 0.1, nx, 1);
  std::vector<double> vx(x_face_count(g), 0.0), kx(x_face_count(g), 0.0);
  for (int f = 1; f < nx; ++f) vx[x_face(g, f, 0)] = V, kx[x_face(g, f, 0)] = K;
  auto m = std::make_unique<Model>(g, std::make_shared<UniformShear>(0.0));
  m->add_term(std::make_unique<CycleAveragedTransport>(vx, kx, std::vector<double>(s_face_count(g), 0.0),
                                                       std::vector<double>(s_face_count(g), 0.0)));
  return m;
}

}  // namespace

TEST_CASE("cycle-averaged transport: BDF reaches the exact steady profile (S1)", "[closure][averaged]") {
  const int nx = 40;
  const double V = 1e-4, K = 1.05e-3;  // r = 1.1: the last cell holds 41x the first
  auto m = uniform_row(nx, V, K);
  const double c0 = 0.05;
  std::vector<double> exact(nx), c(nx, c0);
  const double r = (K + 0.5 * V) / (K - 0.5 * V);
  double sum = 0;
  for (int i = 0; i < nx; ++i) sum += std::pow(r, i);
  for (int i = 0; i < nx; ++i) exact[i] = c0 * nx * std::pow(r, i) / sum;
  // Slowest mode decays as exp(−t/τ), τ ≈ (nx/π)² A/K ≈ 390 s: 1e4 s is 25 τ.
  IntegratorSettings cv{"cvode"};
  cv.rtol = 1e-8, cv.atol = 1e-12;
  auto integ = make_integrator(cv, *m);
  integ->advance(0, 1e4, c);
  double err = 0;
  for (int i = 0; i < nx; ++i) err = std::max(err, std::abs(c[i] - exact[i]) / exact[nx - 1]);
  INFO("max |c − exact| / max exact " << err << ", CVODE steps " << integ->stats().steps << ", max rate "
                                      << m->max_rate(0) << " /s");
  CHECK(exact[nx - 1] / exact[0] > 40);
  CHECK(err < 1e-6);
  CHECK(std::abs(m->chaff(c) - m->chaff(std::vector<double>(nx, c0))) < 1e-13 * m->chaff(c));
  // Not limited by the explicit bound: SSP-RK3 would need 1e4 · max_rate / 0.4 steps.
  CHECK(integ->stats().steps < 1e4 * m->max_rate(0) / 0.4 / 20);
}

TEST_CASE("cycle-averaged transport: the fit recovers V and K, and leaves K unfitted where c_R − c_L is unresolved",
          "[closure][averaged]") {
  const Grid g = Grid::flat(1.0, 0.1, 2, 1);
  const std::size_t face = x_face(g, 1, 0);
  auto fit_face = [&](auto concentrations, auto flux, double& V, double& K) {
    CycleFluxSampler sampler(g);
    FaceFluxes f;
    f.reset(g);
    for (int j = 0; j < 30; ++j) {
      for (int p = 0; p <= 10; ++p) {
        const double t = j + 0.1 * p;
        const auto [cl, cr] = concentrations(t);
        f.x[face] = flux(t, cl, cr);
        sampler.sample(t, f, {cl, cr});
      }
      sampler.end_cycle();
    }
    std::vector<double> vx, kx, vs, ks;
    sampler.fit(vx, kx, vs, ks);
    V = vx[face], K = kx[face];
  };
  double V = 0, K = 0;
  // Resolved: the gradient reverses while the level falls; fluxes exactly (A1) with V = 3e-5, K = 2e-4.
  fit_face([](double t) { return std::pair{0.03 - 5e-4 * t, 0.04 - 1.5e-3 * t}; },
           [](double, double cl, double cr) { return 3e-5 * 0.5 * (cl + cr) - 2e-4 * (cr - cl); }, V, K);
  CHECK(V == Approx(3e-5).epsilon(1e-8));
  CHECK(K == Approx(2e-4).epsilon(1e-8));
  // Unresolved (the static core of a hold): c_R − c_L ~ 2e-8 c, all three drifting together. The
  // least squares would give K ≈ 0.5 m²/s here; the fit must fall back to upwind, K = |V|/2.
  fit_face([](double t) { return std::pair{0.02 - 1e-7 * t, 0.02 - 1e-7 * t + 4.8e-10 * (1 - 0.01 * t)}; },
           [](double t, double, double) { return -4.2e-9 * (1 - 3e-4 * t); }, V, K);
  CHECK(std::abs(V) < 1e-6);
  CHECK(K == Approx(0.5 * std::abs(V)));
}
