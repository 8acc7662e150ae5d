#pragma once
// The calibration's sensitivity figure: the simulated angle of repose against each searched
// parameter (one panel per parameter, side by side), every run as a point with its spread over the
// sectors as a vertical bar, the target as a dashed line with its tolerance band, and the chosen
// value as a dashed vertical line.
#include <string>
#include <vector>

#include "studies/png_image.hpp"

namespace grainscale::studies {

struct SensitivityPoint {
  std::vector<double> values;  // one per parameter
  double angle = 0, spread = 0;  // deg (mean over seeds; spread: mean sector spread)
};

struct SensitivityFigure {
  std::string title;
  std::vector<std::string> parameters;  // axis labels
  std::vector<SensitivityPoint> points;
  double target = 0, tolerance = 0.5;
  std::vector<double> chosen;  // per parameter; empty: none
};

Image draw_sensitivity(const SensitivityFigure& f);

}  // namespace grainscale::studies
