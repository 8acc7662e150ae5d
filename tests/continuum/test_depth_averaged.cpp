// The 1-D depth-averaged variant (depth_averaged.hpp): its equilibrium profile (A2) is the closed-
// form steady column, it conserves chaff to round-off, and it agrees with the 2-D model where it
// should (fast vertical segregation, slow horizontal transport), within a stated tolerance.
#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include "bed_fixture.hpp"
#include "continuum/depth_averaged.hpp"
#include "continuum/fit.hpp"
#include "continuum/integrator.hpp"
#include "continuum/simulate.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;

namespace {

constexpr double pi = std::numbers::pi;

/// z0 of the logistic 1 / (1 + e^{−λ(z − z0)}) with mean `mean` over [0, H] (test_segregation.cpp).
double logistic_z0(double lambda, double H, double mean) {
  auto content = [&](double z0) { return (std::log1p(std::exp(lambda * (H - z0))) - std::log1p(std::exp(-lambda * z0))) / lambda; };
  double lo = -10 * H, hi = 10 * H;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (content(mid) > mean * H ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// A shallow bed (0.4 m × 5 cm) with a weak convection cell (surface speed ≈ 0.3 mm/s, so the
/// horizontal time L/u ≈ 1300 s) and strong segregation (w_s = S γ̇ = 2 mm/s: the vertical time
/// H/w_s = 25 s; λH = w_s H / D ≈ 11).
Model shallow_bed(Closure closure, int nx, int nz, double S = 2e-3, double C = 0.5, double D0 = 1e-6,
                  Limiter limiter = Limiter::van_leer) {
  const double L = 0.4, H = 0.05;
  auto h = [=](double) { return H; };
  auto flow = std::make_shared<CellularFlow>(5e-6, L, h, 1.0);
  Model model(Grid::flat(L, H, nx, nz), flow, closure);
  model.add_term(std::make_unique<Advection>(limiter));
  model.add_term(std::make_unique<Segregation>(S, limiter));
  model.add_term(std::make_unique<ShearDiffusion>(C, 4e-3));
  model.add_term(std::make_unique<BackgroundDiffusion>(D0));
  return model;
}

std::vector<double> column_inventory(const Grid& g, const std::vector<double>& c) {
  std::vector<double> I(g.nx(), 0.0);
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) I[i] += c[g.index(i, k)] * g.dsigma() * g.h_column(i);
  }
  return I;
}

}  // namespace

TEST_CASE("Depth-averaged closure: the equilibrium profile is the steady segregation-diffusion column",
          "[continuum][depth_averaged]") {
  const int N = 200;
  const double H = 0.1;
  for (double lambdaH : {0.0, 5.0, 40.0}) {
    for (double theta : {1e-6, 0.05, 0.3, 0.9}) {
      std::vector<double> Lambda(N), c(N);
      for (int j = 0; j < N; ++j) Lambda[j] = lambdaH * (j + 0.5) / N;
      equilibrium_profile(Lambda, theta, c);
      double mean = 0, worst = 0;
      for (double v : c) mean += v / N;
      if (lambdaH > 0) {
        // The exact profile's mean over the samples is θ only to the midpoint rule's O(1/N²), so
        // compare shapes through the exact z0 for the samples' own mean.
        const double z0 = logistic_z0(lambdaH / H, H, theta);
        for (int j = 0; j < N; ++j) {
          const double z = (j + 0.5) / N * H;
          worst = std::max(worst, std::abs(c[j] - 1 / (1 + std::exp(-lambdaH / H * (z - z0)))));
        }
      } else {
        for (double v : c) worst = std::max(worst, std::abs(v - theta));
      }
      INFO("lambda H = " << lambdaH << ", theta = " << theta << ": mean " << mean << ", max deviation " << worst);
      CHECK(mean == Approx(theta).epsilon(1e-13));
      CHECK(worst < (lambdaH > 20 ? 2e-2 : 2e-4));  // midpoint-rule error, larger for a sharp profile
      CHECK(*std::min_element(c.begin(), c.end()) >= 0);
      CHECK(*std::max_element(c.begin(), c.end()) <= 1);
    }
  }
}

TEST_CASE("Depth-averaged model conserves chaff to round-off", "[continuum][depth_averaged]") {
  const std::string method = GENERATE(as<std::string>{}, "ssp_rk3", "cvode");
  Model model = shallow_bed(Closure::depth_averaged, 40, 10, 2e-3);
  REQUIRE(model.state_size() == 40u);
  std::vector<double> y = model.state(0, block(model.grid()));
  const double m0 = model.state_chaff(y);
  REQUIRE(m0 == Approx(model.chaff(block(model.grid()))).epsilon(1e-14));
  IntegratorSettings s;
  s.method = method;
  auto integrator = make_integrator(s, model);
  double worst = 0;
  for (int j = 0; j < 10; ++j) {
    integrator->advance(100.0 * j, 100.0 * (j + 1), y);
    worst = std::max(worst, std::abs(model.state_chaff(y) - m0) / m0);
    const auto c = model.concentration(100.0 * (j + 1), y);
    worst = std::max(worst, std::abs(model.chaff(c) - m0) / m0);
  }
  INFO(method << ": " << integrator->stats().steps << " steps, worst relative change " << worst);
  REQUIRE(worst < 1e-12);
}

namespace {

struct Agreement {
  double inventory = 0;  // max over outputs (after the first) of max_x |I_1D − I_2D| / max_x I_2D
  double coverage = 0;   // max |coverage_1D − coverage_2D|
  double moved = 0;      // largest change of I_2D over the run, relative to max I_2D
  std::string report;
};

/// 2-D and 1-D runs of the shallow bed from chaff mixed through the depth, more on the left.
Agreement compare_with_2d(double S, double C, double D0) {
  const int nx = 40, nz = 20;
  auto start = [&](const Grid& g) {
    std::vector<double> c(g.cells());
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 0; k < g.nz(); ++k) c[g.index(i, k)] = g.x_centre(i) < 0.2 ? 0.08 : 0.02;
    }
    return c;
  };
  IntegratorSettings s;
  s.method = "cvode";
  s.rtol = 1e-7;
  s.atol = 1e-10;
  const std::vector<double> times{250, 500, 1000, 1500};
  const auto t0 = std::chrono::steady_clock::now();
  Model full = shallow_bed(Closure::resolved, nx, nz, S, C, D0);
  const auto c2 = simulate(full, start(full.grid()), 0, times, s);
  const auto t1 = std::chrono::steady_clock::now();
  Model reduced = shallow_bed(Closure::depth_averaged, nx, nz, S, C, D0);
  const auto c1 = simulate(reduced, start(reduced.grid()), 0, times, s);
  const auto t2 = std::chrono::steady_clock::now();
  const SurfaceCoverage camera(150, 0.004);
  const Grid& g = full.grid();
  std::ostringstream report;
  report << "S = " << S << " m: 2-D " << std::chrono::duration<double>(t1 - t0).count() << " s, 1-D "
         << std::chrono::duration<double>(t2 - t1).count() << " s\n";
  Agreement a;
  const auto I0 = column_inventory(g, start(g));
  for (std::size_t n = 0; n < times.size(); ++n) {
    const auto I2 = column_inventory(g, c2[n]), I1 = column_inventory(g, c1[n]);
    const auto v2 = camera.coverage(g, c2[n]), v1 = camera.coverage(g, c1[n]);
    double dI = 0, scale = 0, dv = 0, change = 0;
    for (int i = 0; i < nx; ++i) {
      dI = std::max(dI, std::abs(I1[i] - I2[i]));
      scale = std::max(scale, I2[i]);
      dv = std::max(dv, std::abs(v1[i] - v2[i]));
      change = std::max(change, std::abs(I2[i] - I0[i]));
    }
    report << "  t = " << times[n] << " s: max |I_1D - I_2D| / max I = " << dI / scale << ", max |coverage| diff " << dv
           << ", inventory moved by up to " << change / scale << " of max\n";
    if (n > 0) {  // after the 2-D model's own segregation transient
      a.inventory = std::max(a.inventory, dI / scale);
      a.coverage = std::max(a.coverage, dv);
    }
    a.moved = std::max(a.moved, change / scale);
  }
  a.report = report.str();
  return a;
}

}  // namespace

TEST_CASE("Depth-averaged model agrees with the 2-D model when vertical segregation is fast",
          "[continuum][depth_averaged]") {
  // Fast: w_s = 2 mm/s, vertical time H / w_s = 25 s against the horizontal L / u ≈ 1300 s.
  const Agreement fast = compare_with_2d(2e-3, 0.5, 1e-6);
  std::printf("%s", fast.report.c_str());
  INFO(fast.report);
  CHECK(fast.moved > 0.2);  // the horizontal transport did something
  CHECK(fast.inventory < 0.03);
  CHECK(fast.coverage < 0.01);
  // Slow: the same profile (λH ≈ 11) reached 20 times more slowly (w_s = 0.1 mm/s, D 20 times
  // smaller): vertical time 500 s, comparable with the horizontal one. The closure's assumption
  // fails and so does the agreement (the 2-D chaff is still rising).
  const Agreement slow = compare_with_2d(1e-4, 0.025, 5e-8);
  std::printf("%s", slow.report.c_str());
  INFO(slow.report);
  CHECK(slow.coverage > 3 * fast.coverage);
}

TEST_CASE("The depth-averaged model is fitted like the 2-D one", "[continuum][depth_averaged][fit]") {
  // Synthetic coverage and fields from the 1-D model itself; S and kappa start 2x off.
  const double S = 1e-3, kappa = 150;
  Model truth = shallow_bed(Closure::depth_averaged, 16, 8, S);
  const SurfaceCoverage camera(kappa, 0.004);
  FitData data;
  data.c0.assign(truth.size(), 0.0);
  for (int i = 0; i < 16; ++i) {
    for (int k = 0; k < 8; ++k) data.c0[truth.grid().index(i, k)] = truth.grid().x_centre(i) < 0.2 ? 0.08 : 0.02;
  }
  data.times = {100, 200, 400};
  IntegratorSettings accurate;
  accurate.method = "ssp_rk3";
  accurate.cfl = 0.1;
  const auto fields = simulate(truth, data.c0, 0, data.times, accurate);
  for (const auto& f : fields) {
    data.fields.push_back(f);
    data.coverage.push_back(camera.coverage(truth.grid(), f));
  }
  data.noise_known = false;
  Model model = shallow_bed(Closure::depth_averaged, 16, 8, 2 * S);
  SurfaceCoverage guess(0.5 * kappa, 0.004);
  FitSettings settings;
  settings.parameters = {"segregation.S", "observation.kappa"};
  const auto t0 = std::chrono::steady_clock::now();
  const FitResult r = fit(model, guess, data, settings);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  INFO(r.status << " after " << r.iterations << " iterations, " << seconds << " s: S = " << r.values[0] << ", kappa = "
                << r.values[1]);
  REQUIRE(r.converged);
  CHECK(r.values[0] == Approx(S).epsilon(1e-3));
  CHECK(r.values[1] == Approx(kappa).epsilon(1e-3));
}

TEST_CASE("Cycle-averaged depth-averaged model follows the cycle-resolved one over many cycles",
          "[continuum][depth_averaged][cycle]") {
  // A shallow bed sloshing ±5 mm every 2 s (linear shear profile) with a convection cell, fast
  // segregation. The cycle-resolved 1-D model steps through every cycle; the averaged one (16
  // phases, A3) has a steady rhs. They differ by the drift that the averaging at fixed I leaves out
  // (the correlation of I's oscillation within the cycle with the flux, second order in the
  // sloshing amplitude).
  SloshingFlow::Shape shape;
  shape.length = 0.4;
  shape.depth = 0.05;
  shape.amplitude = 0.005;
  shape.period = 2.0;
  shape.exponent = 2;
  shape.cell = 2e-5;
  shape.background_shear = 1.0;
  auto build = [&](int phases) {
    auto flow = std::make_shared<SloshingFlow>(shape);
    Model model(Grid::flat(0.4, 0.05, 20, 8), flow, Closure::depth_averaged);
    model.add_term(std::make_unique<Advection>(Limiter::van_leer));
    model.add_term(std::make_unique<Segregation>(2e-3, Limiter::van_leer));
    model.add_term(std::make_unique<ShearDiffusion>(0.5, 4e-3));
    model.add_term(std::make_unique<BackgroundDiffusion>(1e-6));
    if (phases > 0) model.set_cycle_average(shape.period, phases);
    return model;
  };
  Model resolved = build(0), averaged = build(16);
  std::vector<double> c0(resolved.size());
  for (int i = 0; i < 20; ++i) {
    for (int k = 0; k < 8; ++k) c0[resolved.grid().index(i, k)] = resolved.grid().x_centre(i) < 0.2 ? 0.08 : 0.02;
  }
  IntegratorSettings s;
  s.method = "cvode";
  s.rtol = 1e-7;
  s.atol = 1e-10;
  const double t_end = 100;  // 50 cycles; ends at phase 0, where both grids are the rest grid
  auto yr = resolved.state(0, c0), ya = averaged.state(0, c0);
  const double m0 = resolved.state_chaff(yr);
  auto ir = make_integrator(s, resolved), ia = make_integrator(s, averaged);
  ir->advance(0, t_end, yr);
  ia->advance(0, t_end, ya);
  double diff = 0, scale = 0, moved = 0;
  const auto I0 = resolved.state(0, c0);
  for (int i = 0; i < 20; ++i) {
    diff = std::max(diff, std::abs(yr[i] - ya[i]));
    scale = std::max(scale, yr[i]);
    moved = std::max(moved, std::abs(yr[i] - I0[i]));
  }
  INFO("cycle-resolved " << ir->stats().steps << " steps, averaged " << ia->stats().steps
                         << " steps; max |I_avg - I_res| / max I = " << diff / scale << "; I moved by "
                         << moved / scale << " of max");
  std::printf("cycle average: resolved %ld steps, averaged %ld steps, max |I_avg - I_res| / max I = %.3g, moved %.3g\n",
              ir->stats().steps, ia->stats().steps, diff / scale, moved / scale);
  CHECK(std::abs(averaged.state_chaff(ya) - m0) < 1e-12 * m0);
  CHECK(moved / scale > 0.1);
  CHECK(ia->stats().steps * 10 < ir->stats().steps);
  CHECK(diff / scale < 0.02);
}
