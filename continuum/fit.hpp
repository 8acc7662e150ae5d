#pragma once
// Fit model coefficients (any of "segregation.S", "shear_diffusion.C", "background_diffusion.D0",
// "observation.kappa", ... ) to observed concentration fields and/or surface coverage by weighted
// nonlinear least squares: GSL's trust-region Levenberg–Marquardt (gsl_multifit_nlinear) on
// p = log(θ), so the coefficients stay positive. Residuals are (model − data) / σ.
// Uncertainty: with residuals scaled by the known noise, Cov(p) = (JᵀJ)⁻¹ at the optimum; if
// `noise_known` is false it is scaled by χ²/(n − m). Standard errors of θ = e^p by the delta
// method, σ_θ = θ σ_p; correlations from Cov(p).
#include <string>
#include <vector>

#include "continuum/integrator.hpp"
#include "continuum/model.hpp"
#include "continuum/observation.hpp"

namespace grainscale::continuum {

struct FitData {
  double t0 = 0;
  std::vector<double> c0;                     // initial field (cells)
  std::vector<double> times;                  // observation times, increasing, > t0
  std::vector<std::vector<double>> fields;    // c per time (cells); empty: not observed
  std::vector<std::vector<double>> coverage;  // coverage per column per time; empty: not observed
  double field_sigma = 0.01;                  // noise standard deviations
  double coverage_sigma = 0.01;
  bool noise_known = true;
};

struct FitSettings {
  std::vector<std::string> parameters;  // qualified names; "observation.*" address the coverage model
  // SSP-RK3 is the fast choice for these non-stiff runs, and with a step that does not depend on
  // the parameters (max_dt below the stability limit; 0: half the limit at the starting values)
  // the forward map is smooth enough for finite differences. CVODE's adaptive steps are not.
  IntegratorSettings integrator{"ssp_rk3"};
  int max_iterations = 100;
  double xtol = 1e-8, gtol = 1e-10, ftol = 1e-12;
  double fd_step = 1e-6;  // finite-difference step of the Jacobian in log-parameters (relative)
};

struct FitResult {
  std::vector<std::string> names;
  std::vector<double> values, standard_errors;
  std::vector<std::vector<double>> correlation;
  double chi2 = 0;
  int residuals = 0, dof = 0, iterations = 0;
  std::string status;
  bool converged = false;
};

/// Fits in place: on return `model` and `observation` hold the fitted values.
FitResult fit(Model& model, SurfaceCoverage& observation, const FitData& data, const FitSettings& settings);

/// The residual vector (model − data) / σ at the current parameters (also used by the fit's tests).
std::vector<double> fit_residuals(const Model& model, const SurfaceCoverage& observation, const FitData& data,
                                  const IntegratorSettings& integrator);

}  // namespace grainscale::continuum
