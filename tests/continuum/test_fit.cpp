// The fit recovers known coefficients from synthetic data made by the model itself with Gaussian
// noise: within 3 standard errors, and the standard errors are small enough to mean something.
#include <catch2/catch.hpp>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <cmath>

#include "bed_fixture.hpp"
#include "continuum/fit.hpp"
#include "continuum/simulate.hpp"

using namespace grainscale::continuum;
using namespace grainscale::continuum::test;

namespace {

/// Chaff spread through the lower half of the bed: it rises, and the convection cell stirs it.
std::vector<double> lower_half(const Grid& g) {
  std::vector<double> c(g.cells());
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) c[g.index(i, k)] = g.sigma_centre(k) < 0.5 ? 0.3 : 0.02;
  }
  return c;
}

}  // namespace

TEST_CASE("Fitting S, C, D0 and kappa to noisy synthetic fields recovers them", "[continuum][fit]") {
  const double S = 1e-3, C = 0.5, D0 = 2e-6, kappa = 150, delta = 0.01;
  Model truth = full_bed(16, 8, Limiter::van_leer, S, C, D0);
  SurfaceCoverage camera(kappa, delta);
  FitData data;
  data.c0 = lower_half(truth.grid());
  data.times = {25, 50, 100, 200, 400};
  data.field_sigma = 0.01;
  data.coverage_sigma = 0.01;
  IntegratorSettings accurate;
  accurate.method = "ssp_rk3";
  accurate.cfl = 0.1;
  const auto fields = simulate(truth, data.c0, 0, data.times, accurate);
  gsl_rng* rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 20240607);
  for (const auto& f : fields) {
    auto noisy = f;
    for (double& v : noisy) v += gsl_ran_gaussian(rng, data.field_sigma);
    auto cov = camera.coverage(truth.grid(), f);
    for (double& v : cov) v += gsl_ran_gaussian(rng, data.coverage_sigma);
    data.fields.push_back(noisy);
    data.coverage.push_back(cov);
  }
  gsl_rng_free(rng);

  // Start every coefficient off by a factor of 2 to 3.
  Model model = full_bed(16, 8, Limiter::van_leer, 2.5 * S, 0.4 * C, 3 * D0);
  SurfaceCoverage guess(0.5 * kappa, delta);
  FitSettings settings;
  settings.parameters = {"segregation.S", "shear_diffusion.C", "background_diffusion.D0", "observation.kappa"};
  const FitResult r = fit(model, guess, data, settings);
  const std::vector<double> truth_values{S, C, D0, kappa};
  // Stated precision: S and κ are pinned by the segregated profile and the coverage (σ ≈ 1.5 % and
  // 0.5 % here); C and D₀ share the diffusivity and are told apart only by where γ̇ is large, so
  // each is known to ~20 %, with a strong negative correlation.
  const std::vector<double> max_relative_error{0.05, 0.3, 0.3, 0.05};
  std::ostringstream report;
  report << r.status << " after " << r.iterations << " iterations, chi2/dof = " << r.chi2 / r.dof << "\n";
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    report << r.names[j] << " = " << r.values[j] << " ± " << r.standard_errors[j] << " (true " << truth_values[j]
           << ", off by " << (r.values[j] - truth_values[j]) / r.standard_errors[j] << " σ)\n";
  }
  report << "correlation C–D0: " << r.correlation[1][2] << ", S–C: " << r.correlation[0][1] << "\n";
  INFO(report.str());
  REQUIRE(r.converged);
  // χ²/dof ≈ 1 when the model fits down to the noise.
  REQUIRE(r.chi2 / r.dof == Approx(1).margin(0.1));
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    CHECK(std::abs(r.values[j] - truth_values[j]) < 3 * r.standard_errors[j]);
    CHECK(r.standard_errors[j] < max_relative_error[j] * truth_values[j]);
  }
}
