#pragma once
// Figures of a continuum fit (`grainscale fit`): data beside the fitted model and the residual,
// on the model's own grid (terrain-following columns drawn as rectangles of the column's mean
// height), so what was fitted is what is shown.
#include <string>
#include <vector>

#include "continuum/grid.hpp"
#include "studies/fit_observations.hpp"
#include "studies/observed_fit.hpp"
#include "studies/plot.hpp"

namespace grainscale::studies {

/// Cell values (grid order, i * nz + k; NaN: nothing there) as a heat map over (x, z).
HeatMap grid_map(const continuum::Grid& grid, const std::vector<double>& cells, const std::string& title,
                 const std::string& value_label, ColourMap map = ColourMap::sequential);

/// Field data (observed cells), model and residual (model - data) / sigma at time index `time`,
/// stacked top to bottom in one image; data and model share one colour scale.
Image field_comparison(const continuum::Grid& grid, const Observations& data, const Prediction& model, std::size_t time);

/// Coverage along x: data (markers) and model (lines) at up to six of the observed times.
LinePlot coverage_comparison(const continuum::Grid& grid, const Observations& data, const Prediction& model);
/// (model - data) / sigma of the coverage along x, at the same times.
LinePlot coverage_residuals(const continuum::Grid& grid, const Observations& data, const Prediction& model);

/// Histogram of normalised residuals over [-5, 5] (about N(0, 1) if the model and sigma are right).
BarChart residual_histogram(const std::vector<double>& normalised);

/// Indices into data.times that have field (or coverage) observations.
std::vector<std::size_t> field_times(const Observations& data);
std::vector<std::size_t> coverage_times(const Observations& data);

}  // namespace grainscale::studies
