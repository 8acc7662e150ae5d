#include "continuum/fit.hpp"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>

#include <cmath>
#include <stdexcept>

#include "continuum/simulate.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

namespace {

struct Problem {
  Model& model;
  SurfaceCoverage& observation;
  const FitData& data;
  const FitSettings& settings;
  std::size_t residuals;
};

bool is_observation(const std::string& name) { return name.rfind("observation.", 0) == 0; }

double get(const Problem& p, const std::string& name) {
  return is_observation(name) ? p.observation.parameters().get(name.substr(12)) : p.model.parameter(name);
}

void set(Problem& p, const std::string& name, double v) {
  if (is_observation(name)) {
    p.observation.parameters().set(name.substr(12), v);
  } else {
    p.model.set_parameter(name, v);
  }
}

std::size_t residual_count(const FitData& d, const Grid& g) {
  std::size_t n = 0;
  if (!d.fields.empty()) n += d.times.size() * g.cells();
  if (!d.coverage.empty()) n += d.times.size() * static_cast<std::size_t>(g.nx());
  return n;
}

int residual_callback(const gsl_vector* x, void* params, gsl_vector* f) {
  auto& p = *static_cast<Problem*>(params);
  try {
    for (std::size_t j = 0; j < p.settings.parameters.size(); ++j) {
      set(p, p.settings.parameters[j], std::exp(gsl_vector_get(x, j)));
    }
    const std::vector<double> r = fit_residuals(p.model, p.observation, p.data, p.settings.integrator);
    for (std::size_t m = 0; m < r.size(); ++m) gsl_vector_set(f, m, r[m]);
  } catch (const std::exception&) {
    // Outside the admissible range or the integrator failed: a large residual makes the trust
    // region reject the step and shrink, instead of aborting the fit.
    for (std::size_t m = 0; m < p.residuals; ++m) gsl_vector_set(f, m, 1e6);
  }
  return GSL_SUCCESS;
}

}  // namespace

std::vector<double> fit_residuals(const Model& model, const SurfaceCoverage& observation, const FitData& d,
                                  const IntegratorSettings& integrator) {
  std::vector<Grid> grids;  // the grid of each time (it moves with a moving surface)
  const auto fields = simulate(model, d.c0, d.t0, d.times, integrator, {}, &grids);
  const Grid& g = model.grid();
  std::vector<double> r;
  r.reserve(residual_count(d, g));
  for (std::size_t n = 0; n < d.times.size(); ++n) {
    if (!d.fields.empty()) {
      for (std::size_t m = 0; m < g.cells(); ++m) r.push_back((fields[n][m] - d.fields[n][m]) / d.field_sigma);
    }
    if (!d.coverage.empty()) {
      const auto cov = observation.coverage(grids[n], fields[n]);
      for (int i = 0; i < g.nx(); ++i) r.push_back((cov[i] - d.coverage[n][i]) / d.coverage_sigma);
    }
  }
  return r;
}

FitResult fit(Model& model, SurfaceCoverage& observation, const FitData& data, const FitSettings& settings) {
  const std::size_t m = settings.parameters.size();
  if (m == 0) throw InputError("fit: no parameters to fit");
  if (data.times.empty() || (data.fields.empty() && data.coverage.empty())) throw InputError("fit: no data");
  if (!data.fields.empty() && data.fields.size() != data.times.size()) throw InputError("fit: one field per time");
  if (!data.coverage.empty() && data.coverage.size() != data.times.size()) {
    throw InputError("fit: one coverage profile per time");
  }
  FitSettings fixed = settings;
  if (fixed.integrator.method == "ssp_rk3" && fixed.integrator.max_dt <= 0) {
    const double rate = model.max_rate(data.t0);
    fixed.integrator.max_dt = rate > 0 ? 0.5 * fixed.integrator.cfl / rate : data.times.back() - data.t0;
  }
  Problem problem{model, observation, data, fixed, residual_count(data, model.grid())};
  const std::size_t n = problem.residuals;
  if (n <= m) throw InputError("fit: fewer residuals than parameters");
  for (const auto& name : settings.parameters) {
    if (!(get(problem, name) > 0)) throw InputError("fit: " + name + " must start positive (fitted as a logarithm)");
  }

  gsl_multifit_nlinear_fdf fdf;
  fdf.f = residual_callback;
  fdf.df = nullptr;  // forward differences, step fd_step · |p_j|
  fdf.fvv = nullptr;
  fdf.n = n;
  fdf.p = m;
  fdf.params = &problem;
  gsl_multifit_nlinear_parameters fdf_params = gsl_multifit_nlinear_default_parameters();
  fdf_params.h_df = settings.fd_step;
  fdf_params.trs = gsl_multifit_nlinear_trs_lm;
  gsl_multifit_nlinear_workspace* w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fdf_params, n, m);
  gsl_vector* x = gsl_vector_alloc(m);
  gsl_matrix* covar = gsl_matrix_alloc(m, m);
  for (std::size_t j = 0; j < m; ++j) gsl_vector_set(x, j, std::log(get(problem, settings.parameters[j])));

  gsl_multifit_nlinear_init(x, &fdf, w);
  int info = 0;
  const int status = gsl_multifit_nlinear_driver(settings.max_iterations, settings.xtol, settings.gtol, settings.ftol,
                                                 nullptr, nullptr, &info, w);
  FitResult result;
  result.status = gsl_strerror(status);
  result.converged = status == GSL_SUCCESS;
  result.iterations = static_cast<int>(gsl_multifit_nlinear_niter(w));
  const gsl_vector* best = gsl_multifit_nlinear_position(w);
  const gsl_vector* f = gsl_multifit_nlinear_residual(w);
  gsl_blas_ddot(f, f, &result.chi2);
  result.residuals = static_cast<int>(n);
  result.dof = static_cast<int>(n - m);
  gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(w), 0.0, covar);
  const double scale = data.noise_known ? 1.0 : result.chi2 / result.dof;
  result.names = settings.parameters;
  for (std::size_t j = 0; j < m; ++j) {
    const double v = std::exp(gsl_vector_get(best, j));
    set(problem, settings.parameters[j], v);  // leave the model at the optimum
    result.values.push_back(v);
    result.standard_errors.push_back(v * std::sqrt(scale * gsl_matrix_get(covar, j, j)));
  }
  result.correlation.assign(m, std::vector<double>(m));
  for (std::size_t a = 0; a < m; ++a) {
    for (std::size_t b = 0; b < m; ++b) {
      result.correlation[a][b] =
          gsl_matrix_get(covar, a, b) / std::sqrt(gsl_matrix_get(covar, a, a) * gsl_matrix_get(covar, b, b));
    }
  }
  gsl_matrix_free(covar);
  gsl_vector_free(x);
  gsl_multifit_nlinear_free(w);
  return result;
}

}  // namespace grainscale::continuum
