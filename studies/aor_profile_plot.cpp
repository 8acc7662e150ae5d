#include "studies/aor_profile_plot.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "studies/plot.hpp"

namespace grainscale::studies {

Image draw_pile_profile(const AngleMeasurement& m, const std::string& title) {
  LinePlot p;
  p.axes.title = title;
  p.axes.x_label = "distance from the pipe's axis (mm)";
  p.axes.y_label = "surface height (mm)";
  p.axes.width = 900, p.axes.height = 520;
  Series surface{"surface (ring medians)", {}, {}, LineStyle::solid, Marker::circle, Rgb{31, 100, 180}, 2};
  double h_sum = 0, r_sum = 0;
  int n = 0;
  for (std::size_t k = 0; k < m.profile_r.size(); ++k) {
    surface.x.push_back(m.profile_r[k] * 1e3), surface.y.push_back(m.profile_h[k] * 1e3);
    if (m.profile_r[k] >= m.fit_r_inner && m.profile_r[k] <= m.fit_r_outer) h_sum += m.profile_h[k], r_sum += m.profile_r[k], ++n;
  }
  p.series.push_back(surface);
  if (n > 0 && std::isfinite(m.mean_deg)) {
    // The measured angle drawn through the band's centroid of the averaged profile.
    const double slope = -std::tan(m.mean_deg * std::numbers::pi / 180), r0 = r_sum / n, h0 = h_sum / n;
    auto h = [&](double r) { return (h0 + slope * (r - r0)) * 1e3; };
    char name[64];
    std::snprintf(name, sizeof name, "%.2f° (mean over sectors)", m.mean_deg);
    p.series.push_back({name, {m.fit_r_inner * 1e3, m.fit_r_outer * 1e3}, {h(m.fit_r_inner), h(m.fit_r_outer)},
                        LineStyle::dashed, Marker::none, Rgb{200, 30, 45}, 3});
  }
  const double lo = m.base_height * 1e3, hi = m.top_height * 1e3;
  p.series.push_back({"fitted band (20-80 % of height)", {m.fit_r_inner * 1e3, m.fit_r_inner * 1e3, NAN, m.fit_r_outer * 1e3, m.fit_r_outer * 1e3},
                      {lo, hi, NAN, lo, hi}, LineStyle::dashed, Marker::none, Rgb{120, 120, 120}, 1});
  p.axes.x_min = 0;
  p.axes.y_min = 0;
  return draw(p);
}

}  // namespace grainscale::studies
