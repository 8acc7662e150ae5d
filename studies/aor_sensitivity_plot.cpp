#include "studies/aor_sensitivity_plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "studies/plot.hpp"

namespace grainscale::studies {

Image draw_sensitivity(const SensitivityFigure& f) {
  if (f.parameters.empty()) throw std::invalid_argument("sensitivity figure '" + f.title + "': no parameters");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Image> panels;
  for (std::size_t k = 0; k < f.parameters.size(); ++k) {
    LinePlot p;
    p.axes.title = f.parameters.size() == 1 ? f.title : f.title + " (" + std::to_string(k + 1) + "/" +
                                                           std::to_string(f.parameters.size()) + ")";
    p.axes.x_label = f.parameters[k];
    p.axes.y_label = "angle of repose (°)";
    p.axes.width = 760, p.axes.height = 520;
    double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
    double y_lo = f.target - 2 * f.tolerance, y_hi = f.target + 2 * f.tolerance;
    std::vector<std::pair<double, double>> pts;
    Series bars{"sector spread", {}, {}, LineStyle::solid, Marker::none, Rgb{150, 150, 150}, 1};
    for (const SensitivityPoint& q : f.points) {
      if (k >= q.values.size() || !std::isfinite(q.angle)) continue;
      const double x = q.values[k];
      pts.push_back({x, q.angle});
      x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
      y_lo = std::min(y_lo, q.angle - q.spread), y_hi = std::max(y_hi, q.angle + q.spread);
      bars.x.insert(bars.x.end(), {x, x, nan});
      bars.y.insert(bars.y.end(), {q.angle - q.spread, q.angle + q.spread, nan});
    }
    if (k < f.chosen.size()) x_lo = std::min(x_lo, f.chosen[k]), x_hi = std::max(x_hi, f.chosen[k]);
    if (!std::isfinite(x_lo)) x_lo = 0, x_hi = 1;
    if (x_hi - x_lo < 1e-9) x_lo -= 0.05, x_hi += 0.05;
    const double pad = 0.08 * (x_hi - x_lo);
    x_lo -= pad, x_hi += pad;
    std::sort(pts.begin(), pts.end());
    Series runs{"runs", {}, {}, LineStyle::none, Marker::circle, Rgb{31, 100, 180}, 2};
    for (const auto& [x, y] : pts) runs.x.push_back(x), runs.y.push_back(y);
    p.series.push_back({"target", {x_lo, x_hi}, {f.target, f.target}, LineStyle::dashed, Marker::none, Rgb{200, 30, 45}, 2});
    p.series.push_back({"± tolerance", {x_lo, x_hi, nan, x_lo, x_hi},
                        {f.target - f.tolerance, f.target - f.tolerance, nan, f.target + f.tolerance, f.target + f.tolerance},
                        LineStyle::dashed, Marker::none, Rgb{240, 150, 150}, 1});
    if (k < f.chosen.size()) {
      p.series.push_back({"chosen", {f.chosen[k], f.chosen[k]}, {y_lo, y_hi}, LineStyle::dashed, Marker::none,
                          Rgb{40, 150, 60}, 2});
    }
    if (!bars.x.empty()) p.series.push_back(bars);
    p.series.push_back(runs);
    p.axes.x_min = x_lo, p.axes.x_max = x_hi;
    p.legend = LegendPlace::top_left;
    panels.push_back(draw(p));
  }
  int w = 0, h = 0;
  for (const Image& i : panels) w += i.width(), h = std::max(h, i.height());
  Image out(w, h);
  int x = 0;
  for (const Image& i : panels) out.paste(i, x, 0), x += i.width();
  return out;
}

}  // namespace grainscale::studies
