#pragma once
// `grainscale fit SETTINGS.yaml`: fit continuum coefficients (any of S, C, D0, kappa, or any other
// term parameter) to concentration fields and/or top-view coverage profiles, and write the values,
// their standard errors and correlations (fit.yaml), a report (report.md) and figures of data,
// model and residual (PNG). Settings keys: docs/plots.md ("grainscale fit").
//
//   model: continuum.yaml            continuum settings (docs/continuum.md): grid, flow, terms,
//                                    initial, integrator, observation, time.stops
//   data: {fields: f.csv, field_sigma: 0.01, coverage: c.csv, coverage_sigma: 0.02, t0: 0}
//   fit:  {parameters: [S, C, D0, kappa], start: {S: 2e-3}, max_iterations: 100,
//          integrator: ssp_rk3, cfl: 0.4, max_dt: 0, fd_step: 1e-6}
//   output: fit_out
#include <map>
#include <string>
#include <vector>

#include "continuum/fit.hpp"
#include "continuum/settings.hpp"
#include "studies/fit_observations.hpp"

namespace grainscale::studies {

struct FitCommandSettings {
  std::string source_file;
  std::string model_file;
  continuum::ContinuumSettings model;
  ObservationFiles data;
  double t0 = 0;
  continuum::FitSettings fit;          // fit.parameters: qualified names, in the order given
  std::map<std::string, double> start;  // qualified name -> starting value (others: the model's)
  std::string output_folder;
};

/// The names `fit.parameters` accepts for a model: the short names S, C, D0, kappa, every qualified
/// parameter of the model's terms, observation.kappa and observation.delta.
std::vector<std::string> fittable_parameters(const continuum::ContinuumSettings& model_settings);

/// Read and check the settings: unknown keys, unknown parameters, bad ranges and missing files are
/// InputErrors naming file, line and key. Relative paths are relative to the settings file.
FitCommandSettings load_fit_command_settings(const std::string& yaml_file);

struct FitCommandSummary {
  continuum::FitResult result;
  std::vector<double> start_values;
  std::size_t field_observations = 0, coverage_observations = 0;
  std::vector<std::string> files;  // written, in the output folder
  /// Why the result should not be trusted (not converged, a parameter the data do not constrain);
  /// empty for a sound fit. Strong correlations are noted in the report, not here.
  std::vector<std::string> warnings;
};

/// Map the data, fit, and write fit.yaml, report.md and the figures into settings.output_folder.
FitCommandSummary run_fit_command(const FitCommandSettings& settings);

/// The command line: `grainscale fit SETTINGS.yaml [--out DIR]` (positional arguments after the
/// command). Prints a summary; returns the exit code: 0, or 4 if there are warnings.
int fit_command(const std::vector<std::string>& positional, const std::string& out);

}  // namespace grainscale::studies
