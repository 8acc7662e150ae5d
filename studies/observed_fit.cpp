#include "studies/observed_fit.hpp"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>

#include <cmath>
#include <memory>

#include "continuum/simulate.hpp"
#include "dem/input_error.hpp"

namespace grainscale::studies {

using continuum::FitResult;
using continuum::FitSettings;
using continuum::Model;
using continuum::SurfaceCoverage;

namespace {

bool is_observation(const std::string& name) { return name.rfind("observation.", 0) == 0; }

double get(const Model& m, const SurfaceCoverage& o, const std::string& name) {
  return is_observation(name) ? o.parameters().get(name.substr(12)) : m.parameter(name);
}

void set(Model& m, SurfaceCoverage& o, const std::string& name, double v) {
  if (is_observation(name)) o.parameters().set(name.substr(12), v);
  else m.set_parameter(name, v);
}

struct Problem {
  Model& model;
  SurfaceCoverage& observation;
  const ModelStart& start;
  const Observations& data;
  const FitSettings& settings;
  std::size_t residuals;
};

int residual_callback(const gsl_vector* x, void* params, gsl_vector* f) {
  auto& p = *static_cast<Problem*>(params);
  try {
    for (std::size_t j = 0; j < p.settings.parameters.size(); ++j) {
      set(p.model, p.observation, p.settings.parameters[j], std::exp(gsl_vector_get(x, j)));
    }
    const auto r = observation_residuals(predict(p.model, p.observation, p.start, p.data.times, p.settings.integrator), p.data);
    for (std::size_t m = 0; m < r.size(); ++m) gsl_vector_set(f, m, r[m]);
  } catch (const std::exception&) {
    // Outside the admissible range, or the integrator failed: as in continuum::fit, a large
    // residual makes the trust region reject the step and shrink.
    for (std::size_t m = 0; m < p.residuals; ++m) gsl_vector_set(f, m, 1e6);
  }
  return GSL_SUCCESS;
}

struct GslFree {
  void operator()(gsl_multifit_nlinear_workspace* w) const { gsl_multifit_nlinear_free(w); }
  void operator()(gsl_vector* v) const { gsl_vector_free(v); }
  void operator()(gsl_matrix* m) const { gsl_matrix_free(m); }
};

}  // namespace

Prediction predict(const Model& model, const SurfaceCoverage& observation, const ModelStart& start,
                   const std::vector<double>& times, const continuum::IntegratorSettings& integrator) {
  Prediction p;
  p.fields = continuum::simulate(model, start.c0, start.t0, times, integrator, start.stops);
  for (const auto& c : p.fields) p.coverage.push_back(observation.coverage(model.grid(), c));
  return p;
}

std::vector<double> observation_residuals(const Prediction& p, const Observations& data) {
  std::vector<double> r;
  r.reserve(data.fields.size() + data.coverage.size());
  for (const Observation& o : data.fields) r.push_back((p.fields[o.time][o.index] - o.value) / o.sigma);
  for (const Observation& o : data.coverage) r.push_back((p.coverage[o.time][o.index] - o.value) / o.sigma);
  return r;
}

FitResult fit_observations(Model& model, SurfaceCoverage& observation, const ModelStart& start, const Observations& data,
                           const FitSettings& settings) {
  const std::size_t m = settings.parameters.size();
  const std::size_t n = data.fields.size() + data.coverage.size();
  if (m == 0) throw InputError("fit: no parameters to fit");
  if (n <= m) {
    throw InputError("fit: " + std::to_string(n) + " observations for " + std::to_string(m) + " parameters (need more)");
  }
  for (const auto& name : settings.parameters) {
    if (!(get(model, observation, name) > 0)) throw InputError("fit: " + name + " must start positive (fitted as a logarithm)");
  }
  FitSettings fixed = settings;
  if (fixed.integrator.method == "ssp_rk3" && fixed.integrator.max_dt <= 0) {
    // A step that does not change with the parameters keeps the forward map smooth for the
    // finite-difference Jacobian (continuum/fit.hpp).
    const double rate = model.max_rate(start.t0);
    fixed.integrator.max_dt = rate > 0 ? 0.5 * fixed.integrator.cfl / rate : data.times.back() - start.t0;
  }
  Problem problem{model, observation, start, data, fixed, n};

  gsl_multifit_nlinear_fdf fdf;
  fdf.f = residual_callback;
  fdf.df = nullptr;  // forward differences
  fdf.fvv = nullptr;
  fdf.n = n;
  fdf.p = m;
  fdf.params = &problem;
  gsl_multifit_nlinear_parameters fdf_params = gsl_multifit_nlinear_default_parameters();
  fdf_params.h_df = settings.fd_step;
  fdf_params.trs = gsl_multifit_nlinear_trs_lm;
  std::unique_ptr<gsl_multifit_nlinear_workspace, GslFree> w(
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fdf_params, n, m));
  std::unique_ptr<gsl_vector, GslFree> x(gsl_vector_alloc(m));
  std::unique_ptr<gsl_matrix, GslFree> covar(gsl_matrix_alloc(m, m));
  for (std::size_t j = 0; j < m; ++j) gsl_vector_set(x.get(), j, std::log(get(model, observation, settings.parameters[j])));

  gsl_multifit_nlinear_init(x.get(), &fdf, w.get());
  int info = 0;
  const int status = gsl_multifit_nlinear_driver(settings.max_iterations, settings.xtol, settings.gtol, settings.ftol,
                                                 nullptr, nullptr, &info, w.get());
  FitResult result;
  result.status = gsl_strerror(status);
  result.converged = status == GSL_SUCCESS;
  result.iterations = static_cast<int>(gsl_multifit_nlinear_niter(w.get()));
  const gsl_vector* best = gsl_multifit_nlinear_position(w.get());
  gsl_blas_ddot(gsl_multifit_nlinear_residual(w.get()), gsl_multifit_nlinear_residual(w.get()), &result.chi2);
  result.residuals = static_cast<int>(n);
  result.dof = static_cast<int>(n - m);
  gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(w.get()), 0.0, covar.get());
  const double scale = data.sigma_known ? 1.0 : result.chi2 / result.dof;
  result.names = settings.parameters;
  for (std::size_t j = 0; j < m; ++j) {
    const double v = std::exp(gsl_vector_get(best, j));
    set(model, observation, settings.parameters[j], v);  // leave the model at the optimum
    result.values.push_back(v);
    result.standard_errors.push_back(v * std::sqrt(scale * gsl_matrix_get(covar.get(), j, j)));
  }
  result.correlation.assign(m, std::vector<double>(m));
  for (std::size_t a = 0; a < m; ++a) {
    for (std::size_t b = 0; b < m; ++b) {
      result.correlation[a][b] = gsl_matrix_get(covar.get(), a, b) /
                                 std::sqrt(gsl_matrix_get(covar.get(), a, a) * gsl_matrix_get(covar.get(), b, b));
    }
  }
  return result;
}

}  // namespace grainscale::studies
