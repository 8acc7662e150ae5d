#include "studies/fit_plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

namespace grainscale::studies {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string at_time(double t) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "t = %.4g s", t);
  return buf;
}

std::vector<std::size_t> times_of(const std::vector<Observation>& obs) {
  std::set<std::size_t> s;
  for (const auto& o : obs) s.insert(o.time);
  return {s.begin(), s.end()};
}

/// At most `n` entries, evenly spread, first and last included.
std::vector<std::size_t> thin(const std::vector<std::size_t>& v, std::size_t n) {
  if (v.size() <= n) return v;
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < n; ++k) out.push_back(v[k * (v.size() - 1) / (n - 1)]);
  return out;
}

std::vector<double> column_centres(const continuum::Grid& g) {
  std::vector<double> x;
  for (int i = 0; i < g.nx(); ++i) x.push_back(g.x_centre(i));
  return x;
}

}  // namespace

std::vector<std::size_t> field_times(const Observations& d) { return times_of(d.fields); }
std::vector<std::size_t> coverage_times(const Observations& d) { return times_of(d.coverage); }

HeatMap grid_map(const continuum::Grid& g, const std::vector<double>& cells, const std::string& title,
                 const std::string& value_label, ColourMap map) {
  HeatMap h;
  h.axes.title = title;
  h.axes.x_label = "x along the bed (m)";
  h.axes.y_label = "z (m)";
  h.axes.height = 330;
  h.value_label = value_label;
  h.map = map;
  for (int f = 0; f <= g.nx(); ++f) h.x_edges.push_back(g.x_face(f));
  for (int i = 0; i < g.nx(); ++i)
    for (int m = 0; m <= g.nz(); ++m) h.y_edges.push_back(g.sigma_face(m) * g.h_column(i));
  h.values.assign(g.cells(), kNaN);
  for (int i = 0; i < g.nx(); ++i)
    for (int k = 0; k < g.nz(); ++k) h.values[static_cast<std::size_t>(k) * g.nx() + i] = cells[g.index(i, k)];
  h.axes.y_min = 0;
  return h;
}

Image field_comparison(const continuum::Grid& g, const Observations& d, const Prediction& p, std::size_t n) {
  std::vector<double> data(g.cells(), kNaN), residual(g.cells(), kNaN);
  for (const Observation& o : d.fields) {
    if (o.time != n) continue;
    data[o.index] = o.value;
    residual[o.index] = (p.fields[n][o.index] - o.value) / o.sigma;
  }
  double hi = 0;
  for (double v : data)
    if (std::isfinite(v)) hi = std::max(hi, v);
  for (double v : p.fields[n]) hi = std::max(hi, v);
  const std::string when = at_time(d.times[n]);
  HeatMap a = grid_map(g, data, "Data: chaff concentration c, " + when + " (grey: not observed)", "c (-)");
  HeatMap b = grid_map(g, p.fields[n], "Fitted model: c, " + when, "c (-)");
  HeatMap r = grid_map(g, residual, "Residual (model - data) / σ, " + when, "(model - data) / σ", ColourMap::diverging);
  for (HeatMap* h : {&a, &b}) {
    h->v_min = 0;
    h->v_max = hi > 0 ? hi : 1;
  }
  const Image ia = draw(a), ib = draw(b), ir = draw(r);
  Image out(std::max({ia.width(), ib.width(), ir.width()}), ia.height() + ib.height() + ir.height());
  out.paste(ia, 0, 0);
  out.paste(ib, 0, ia.height());
  out.paste(ir, 0, ia.height() + ib.height());
  return out;
}

LinePlot coverage_comparison(const continuum::Grid& g, const Observations& d, const Prediction& p) {
  LinePlot plot;
  plot.axes.title = "Top-view chaff coverage: data (points) and fitted model (lines)";
  plot.axes.x_label = "x along the bed (m)";
  plot.axes.y_label = "coverage (-)";
  plot.axes.y_min = 0;
  const std::vector<double> x = column_centres(g);
  std::size_t colour = 0;
  for (std::size_t n : thin(coverage_times(d), 6)) {
    std::vector<double> data(static_cast<std::size_t>(g.nx()), kNaN);
    for (const Observation& o : d.coverage)
      if (o.time == n) data[o.index] = o.value;
    const Rgb c = palette(colour++);
    plot.series.push_back({"data, " + at_time(d.times[n]), x, data, LineStyle::none, Marker::circle, c});
    plot.series.push_back({"", x, p.coverage[n], LineStyle::solid, Marker::none, c});
  }
  return plot;
}

LinePlot coverage_residuals(const continuum::Grid& g, const Observations& d, const Prediction& p) {
  LinePlot plot;
  plot.axes.title = "Coverage residual (model - data) / σ";
  plot.axes.x_label = "x along the bed (m)";
  plot.axes.y_label = "(model - data) / σ";
  const std::vector<double> x = column_centres(g);
  std::size_t colour = 0;
  for (std::size_t n : thin(coverage_times(d), 6)) {
    std::vector<double> r(static_cast<std::size_t>(g.nx()), kNaN);
    for (const Observation& o : d.coverage)
      if (o.time == n) r[o.index] = (p.coverage[n][o.index] - o.value) / o.sigma;
    plot.series.push_back({at_time(d.times[n]), x, r, LineStyle::solid, Marker::circle, palette(colour++)});
  }
  plot.series.push_back({"", {0.0, g.length()}, {0.0, 0.0}, LineStyle::dashed, Marker::none, Rgb{100, 100, 100}, 1});
  return plot;
}

BarChart residual_histogram(const std::vector<double>& r) {
  BarChart c;
  for (int k = 0; k <= 20; ++k) c.edges.push_back(-5.0 + 0.5 * k);
  std::size_t outside = 0;
  for (double v : r)
    if (std::isfinite(v) && std::abs(v) > 5) ++outside;
  c.axes.title = "Normalised residuals (model - data) / σ of all observations";
  if (outside > 0) c.axes.title += " (" + std::to_string(outside) + " beyond ±5)";
  c.axes.x_label = "(model - data) / σ";
  c.axes.y_label = "observations";
  c.series.push_back({"residuals", histogram(r, c.edges)});
  // What N(0, 1) gives for the same count: the bin's probability times the number of residuals.
  std::vector<double> expected;
  std::size_t finite = 0;
  for (double v : r) finite += std::isfinite(v);
  for (std::size_t k = 0; k + 1 < c.edges.size(); ++k) {
    const double p = 0.5 * (std::erf(c.edges[k + 1] / std::sqrt(2.0)) - std::erf(c.edges[k] / std::sqrt(2.0)));
    expected.push_back(p * static_cast<double>(finite));
  }
  c.series.push_back({"expected: N(0, 1)", expected, Rgb{190, 190, 190}});
  return c;
}

}  // namespace grainscale::studies
