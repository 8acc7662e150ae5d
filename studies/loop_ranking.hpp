#pragma once
// Steps 1, 3 and 4 of `grainscale loop` (docs/loop.md): fit a model (the base, or the base plus one
// candidate effect) to all data, and score it honestly.
//  - Information criteria of the full-data fit: AIC = χ² + 2k and BIC = χ² + k ln n when σ is
//    known (n ln(χ²/n) + ... when it is estimated), k the number of fitted parameters.
//  - Blocked cross-validation: the observations are cut into K contiguous blocks of time (or of x,
//    when there are fewer than K observation times); each block in turn is held out, the model is
//    refitted to the rest (starting from the full-data optimum, at most 10 iterations) and predicts
//    the block. Whole
//    blocks, never single points, so the error of a smooth structure is not hidden by its
//    neighbours. CV error = sqrt(mean of the held-out r²).
// A candidate is added only if it lowers the held-out χ² (mean r²) by at least `min_cv_gain`
// (relative) AND
// lowers BIC by at least `bic_drop` (10: "very strong", Kass & Raftery 1995) AND its strength is
// constrained (standard error below the value).
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "continuum/fit.hpp"
#include "continuum/model.hpp"
#include "continuum/observation.hpp"
#include "studies/fit_observations.hpp"
#include "studies/observed_fit.hpp"

namespace grainscale::studies {

/// Where a fit restarts a parameter that the data drove to zero: on log-parameters its logarithm
/// runs off and exp underflows to exactly 0, from which no fit can start. 1e-200 of its unit is
/// still negligible for any coefficient here, and a fit can climb back from it if the data ask.
inline constexpr double kRanToZero = 1e-200;

struct CvSettings {
  std::string by = "auto";  // time | x | auto (time if there are at least `blocks` observation times)
  int blocks = 4;
};

struct ModelFactory {
  /// A fresh model and observation operator at their starting values.
  std::function<continuum::Model()> model;
  std::function<continuum::SurfaceCoverage()> observation;
};

struct Evaluation {
  std::string name;
  std::vector<std::string> parameters;
  continuum::FitResult fit;          // full-data fit
  std::vector<double> values, standard_errors;
  /// Per parameter: the fit ended at the edge of its admissible range (e.g. lever_arm.S at 1 m):
  /// pressed against a bound, its standard error says nothing about its uncertainty.
  std::vector<bool> at_bound;
  Prediction prediction;             // at the full-data optimum
  double chi2 = 0, aic = 0, bic = 0;
  int n = 0, k = 0;
  double rmse_fields = NAN, max_fields = NAN, rmse_coverage = NAN, max_coverage = NAN;  // data units
  double rms = 0;                    // sqrt(mean r²) of the full fit
  std::string cv_by;
  int cv_folds = 0, cv_points = 0;
  double cv_error = NAN;             // sqrt(mean held-out r²)
  /// With known sigma, the part of the CV error the noise does not explain: sqrt(max(cv² − 1, 0))
  /// (r has unit variance where the model is right). NaN when sigma is estimated.
  double cv_model_error = NAN;
  double cv_rmse_fields = NAN, cv_rmse_coverage = NAN;  // data units
  std::vector<std::string> warnings;
  double seconds = 0;
  bool ok = false;                   // the fit ran (a failed candidate is reported, not ranked)
  std::string error;
};

struct Problem {
  ModelStart start;
  const Observations* data = nullptr;
  continuum::FitSettings fit;  // integrator, iterations, fd step (parameters ignored)
  CvSettings cv;
};

/// The fold (0..K−1) of each observation (fields first, then coverage), and the resolved `by`.
std::vector<int> cv_folds(const continuum::Grid& grid, const Observations& data, const CvSettings& cv, std::string& by);

/// Fit `parameters` (starting values from the factory) to all data, then run the blocked CV.
Evaluation evaluate(const std::string& name, const ModelFactory& factory, const std::vector<std::string>& parameters,
                    const Problem& problem);

}  // namespace grainscale::studies
