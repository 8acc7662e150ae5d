#pragma once
// The continuum fit of continuum/fit.hpp, for data that cover only some cells and columns and carry
// their own sigma (fit_observations.hpp): the same weighted least squares on log-parameters with
// GSL's trust-region Levenberg–Marquardt, the same FitSettings and FitResult, but residuals
// (model − value) / sigma only where there are observations. continuum::FitData takes complete
// fields with one sigma; measured and coarse-grained data are sparse (cells without particles) and
// heteroscedastic. tests/studies/test_fit_command.cpp checks that on complete, uniform data both
// fits agree.
#include <vector>

#include "continuum/fit.hpp"
#include "continuum/model.hpp"
#include "continuum/observation.hpp"
#include "studies/fit_observations.hpp"

namespace grainscale::studies {

/// The model's start: its initial field at t0, and the forcing jumps to stop at.
struct ModelStart {
  std::vector<double> c0;
  double t0 = 0;
  std::vector<double> stops;
};

struct Prediction {
  std::vector<std::vector<double>> fields;    // c per time (cells)
  std::vector<std::vector<double>> coverage;  // per time (columns)
};

/// The model at every observation time.
Prediction predict(const continuum::Model& model, const continuum::SurfaceCoverage& observation, const ModelStart& start,
                   const std::vector<double>& times, const continuum::IntegratorSettings& integrator);

/// (model − value) / sigma: the field observations in order, then the coverage observations.
std::vector<double> observation_residuals(const Prediction& p, const Observations& data);

/// Fits in place (the model and observation hold the fitted values on return). The standard
/// errors are scaled by chi2/dof when data.sigma_known is false.
continuum::FitResult fit_observations(continuum::Model& model, continuum::SurfaceCoverage& observation,
                                      const ModelStart& start, const Observations& data,
                                      const continuum::FitSettings& settings);

}  // namespace grainscale::studies
