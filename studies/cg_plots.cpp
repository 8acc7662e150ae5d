#include "studies/cg_plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>

#include "dem/input_error.hpp"

namespace grainscale::studies {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Row indices of each time, in file order (the cg driver writes one block of rows per snapshot).
std::vector<std::vector<std::size_t>> rows_by_time(const std::vector<double>& t, std::vector<double>& times) {
  std::vector<std::vector<std::size_t>> out;
  for (std::size_t r = 0; r < t.size(); ++r) {
    if (times.empty() || t[r] != times.back()) {
      times.push_back(t[r]);
      out.emplace_back();
    }
    out.back().push_back(r);
  }
  return out;
}

bool any_finite(const std::vector<double>& v, const std::vector<std::size_t>& rows) {
  return std::any_of(rows.begin(), rows.end(), [&](std::size_t r) { return std::isfinite(v[r]); });
}

/// The first and the last time that has a finite value (snapshots before the chaff is poured
/// have none). InputError if there is none at all.
std::pair<std::size_t, std::size_t> first_and_last(const std::vector<double>& v, const std::vector<std::vector<std::size_t>>& groups,
                                                   const NumericCsv& csv, const std::string& column) {
  std::size_t first = groups.size(), last = groups.size();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (!any_finite(v, groups[g])) continue;
    if (first == groups.size()) first = g;
    last = g;
  }
  if (first == groups.size()) throw InputError(csv.name() + ": column '" + column + "' has no finite value");
  return {first, last};
}

std::vector<double> pick(const std::vector<double>& v, const std::vector<std::size_t>& rows, double factor = 1) {
  std::vector<double> out;
  for (std::size_t r : rows) out.push_back(factor * v[r]);
  return out;
}

std::string seconds(double t) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "t = %.3g s", t);
  return buf;
}

/// Cell edges from sorted, equally spaced centres (the cg grid is uniform per axis).
std::vector<double> edges_from_centres(const std::vector<double>& c) {
  std::vector<double> e;
  const double h = c.size() > 1 ? c[1] - c[0] : 1.0;
  e.push_back(c.front() - 0.5 * h);
  for (std::size_t k = 0; k + 1 < c.size(); ++k) e.push_back(0.5 * (c[k] + c[k + 1]));
  e.push_back(c.back() + 0.5 * h);
  return e;
}

std::vector<double> sorted_unique(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

}  // namespace

BarChart slices_figure(const NumericCsv& csv) {
  const auto t = csv.column("t_s"), pct = csv.column("chaff_percent"), lo = csv.column("x_lo_m"), hi = csv.column("x_hi_m");
  std::vector<double> times;
  const auto groups = rows_by_time(t, times);
  const auto [first, last] = first_and_last(pct, groups, csv, "chaff_percent");
  BarChart c;
  for (std::size_t r : groups[first]) c.edges.push_back(lo[r]);
  c.edges.push_back(hi[groups[first].back()]);
  if (groups[last].size() != groups[first].size()) {
    throw InputError(csv.name() + ": the first and last snapshots have different slices");
  }
  char title[96];
  std::snprintf(title, sizeof title, "Chaff per %.3g mm slice (report Figure 11)", 1e3 * (c.edges[1] - c.edges[0]));
  c.axes.title = title;
  c.axes.x_label = "x along the box (m)";
  c.axes.y_label = "chaff in slice (% of all chaff)";
  c.series.push_back({"initial, " + seconds(times[first]), pick(pct, groups[first])});
  if (last != first) c.series.push_back({"final, " + seconds(times[last]), pick(pct, groups[last])});
  return c;
}

LinePlot coverage_figure(const NumericCsv& csv) {
  const auto t = csv.column("t_s"), x = csv.column("x_m"), cov = csv.column("coverage");
  const auto lo = csv.column("x_lo_m"), hi = csv.column("x_hi_m");
  std::vector<double> times;
  const auto groups = rows_by_time(t, times);
  const auto [first, last] = first_and_last(cov, groups, csv, "coverage");
  LinePlot p;
  p.axes.title = "Top-view chaff coverage along the box";
  p.axes.x_label = "x along the box (m)";
  p.axes.y_label = "chaff coverage (% of top-view pixels)";
  p.axes.y_min = 0;
  p.axes.y_max = 100;
  p.series.push_back({"first, " + seconds(times[first]), pick(x, groups[first]), pick(cov, groups[first], 100.0),
                      LineStyle::solid, Marker::circle});
  if (last != first) {
    p.series.push_back({"last, " + seconds(times[last]), pick(x, groups[last]), pick(cov, groups[last], 100.0),
                        LineStyle::solid, Marker::square});
  }
  // The report's photographs: ~60 % over each end zone, ~10 % over a central zone of the same length.
  const double x0 = lo[groups[first].front()], x1 = hi[groups[first].back()], mid = 0.5 * (x0 + x1);
  const double e = std::min(kReportEndZone, 0.5 * (x1 - x0));
  p.series.push_back({"report (wheat, 30 min): ends ~60 %", {x0, x0 + e, kNaN, x1 - e, x1},
                      {100 * kReportCoverageEnds, 100 * kReportCoverageEnds, kNaN, 100 * kReportCoverageEnds, 100 * kReportCoverageEnds},
                      LineStyle::dashed, Marker::none, Rgb{200, 30, 45}, 3});
  p.series.push_back({"report: centre ~10 %", {mid - 0.5 * e, mid + 0.5 * e}, {100 * kReportCoverageCentre, 100 * kReportCoverageCentre},
                      LineStyle::dashed, Marker::none, Rgb{120, 70, 175}, 3});
  return p;
}

LinePlot congregation_figure(const NumericCsv& csv) {
  const auto t = csv.column("t_s"), left = csv.column("index_left"), right = csv.column("index_right");
  const bool few = t.size() <= 40;
  LinePlot p;
  p.axes.title = "Congregation index: chaff fraction at an end / overall";
  p.axes.x_label = "t (s)";
  p.axes.y_label = "congregation index (1: uniform)";
  p.axes.y_min = 0;
  p.series.push_back({"left end", t, left, LineStyle::solid, few ? Marker::circle : Marker::none});
  p.series.push_back({"right end", t, right, LineStyle::solid, few ? Marker::square : Marker::none});
  double t0 = kNaN, t1 = kNaN;
  for (std::size_t r = 0; r < t.size(); ++r) {
    if (!std::isfinite(left[r]) && !std::isfinite(right[r])) continue;
    if (std::isnan(t0)) t0 = t[r];
    t1 = t[r];
  }
  if (std::isnan(t0)) throw InputError(csv.name() + ": no finite congregation index");
  p.series.push_back({"uniform mixture", {t0, t1}, {1.0, 1.0}, LineStyle::dashed, Marker::none, Rgb{100, 100, 100}, 1});
  return p;
}

HeatMap concentration_figure(const NumericCsv& csv) {
  const auto t = csv.column("t_s"), x = csv.column("x_m"), z = csv.column("z_m"), c = csv.column("c");
  if (t.empty()) throw InputError(csv.name() + ": no rows");
  const double last = *std::max_element(t.begin(), t.end());
  std::vector<double> xs, zs;
  for (std::size_t r = 0; r < t.size(); ++r) {
    if (t[r] != last) continue;
    xs.push_back(x[r]);
    zs.push_back(z[r]);
  }
  xs = sorted_unique(xs);
  zs = sorted_unique(zs);
  if (zs.size() < 2) throw InputError(csv.name() + ": the fields have one height (a 1-D grid): no c(x, z) to map");
  // Mean over y (3-D grids) of the cells with chaff data; cells without particles stay NaN.
  std::vector<double> sum(xs.size() * zs.size(), 0.0), count(sum.size(), 0.0);
  for (std::size_t r = 0; r < t.size(); ++r) {
    if (t[r] != last || !std::isfinite(c[r])) continue;
    const auto i = static_cast<std::size_t>(std::lower_bound(xs.begin(), xs.end(), x[r]) - xs.begin());
    const auto k = static_cast<std::size_t>(std::lower_bound(zs.begin(), zs.end(), z[r]) - zs.begin());
    sum[k * xs.size() + i] += c[r];
    count[k * xs.size() + i] += 1;
  }
  HeatMap h;
  h.axes.title = "Chaff volume concentration c(x, z), " + seconds(last);
  h.axes.width = 1000;
  h.axes.x_label = "x along the box (m)";
  h.axes.y_label = "z (m)";
  h.value_label = "c (-)";
  h.x_edges = edges_from_centres(xs);
  h.y_edges = edges_from_centres(zs);
  for (std::size_t q = 0; q < sum.size(); ++q) h.values.push_back(count[q] > 0 ? sum[q] / count[q] : kNaN);
  h.v_min = 0;
  h.equal_aspect = true;
  return h;
}

CgPlotReport write_cg_plots(const std::string& output_dir, std::ostream& log) {
  namespace fs = std::filesystem;
  CgPlotReport report;
  auto attempt = [&](const std::string& csv_name, const std::string& png_name, auto build) {
    const std::string png = (fs::path(output_dir) / png_name).string();
    try {
      const NumericCsv csv = NumericCsv::load((fs::path(output_dir) / csv_name).string());
      draw(build(csv)).write_png(png);
      report.written.push_back(png);
      log << "plot: " << png << "\n";
    } catch (const std::exception& e) {  // input errors and nothing-to-plot alike: skip, say why
      report.skipped.push_back(png_name + ": " + e.what());
      log << "no plot " << png_name << ": " << e.what() << "\n";
    }
  };
  attempt("slices.csv", "slices.png", slices_figure);
  attempt("coverage.csv", "coverage.png", coverage_figure);
  attempt("congregation.csv", "congregation.png", congregation_figure);
  attempt("fields.csv", "concentration.png", concentration_figure);
  return report;
}

}  // namespace grainscale::studies
