#include "studies/plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "studies/bitmap_font.hpp"
#include "studies/nice_ticks.hpp"

namespace grainscale::studies {

namespace {

constexpr int kText = 2;                      // font scale of all text: 10 x 14 px glyphs
constexpr int kTextHeight = kGlyphHeight * kText;
constexpr int kTickLength = 6;
constexpr int kPad = 12;                      // between figure edge, labels and frame
constexpr int kColourBarGap = 16, kColourBarWidth = 22;
constexpr Rgb kInk{0, 0, 0}, kGridColour{228, 228, 228}, kLegendBorder{140, 140, 140}, kWhite{255, 255, 255};

constexpr Rgb kPalette[] = {{0, 90, 181},  {220, 110, 0}, {26, 140, 60},   {200, 30, 45},
                            {120, 70, 175}, {140, 86, 55}, {210, 80, 160}, {100, 100, 100}};

std::string quoted(const Axes& a) { return a.title.empty() ? std::string("(untitled)") : "'" + a.title + "'"; }

struct Extent {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return lo > hi; }
};

/// Ticks for one axis. `widen`: round the data's ends out to ticks (a fixed limit is kept as given).
Ticks axis_ticks(Extent data, std::optional<double> fixed_lo, std::optional<double> fixed_hi, bool widen, int target,
                 const std::string& figure, const char* axis) {
  const double a = fixed_lo.value_or(data.lo), b = fixed_hi.value_or(data.hi);
  if ((fixed_lo || fixed_hi) && !(a < b)) {
    throw std::invalid_argument("figure " + figure + ": the " + axis + " axis limits leave no range (min >= max)");
  }
  Ticks t = widen || a == b ? nice_ticks(a, b, target) : ticks_within(a, b, target);
  if (fixed_lo || fixed_hi) {  // a fixed end is kept as given; a free end stays rounded out
    if (fixed_lo) t.lo = a;
    if (fixed_hi) t.hi = b;
    std::vector<double> inside;
    for (double v : t.values)
      if (v >= t.lo - 1e-9 * t.step && v <= t.hi + 1e-9 * t.step) inside.push_back(v);
    t.values = inside;
  }
  return t;
}

int widest(const std::vector<std::string>& labels) {
  int w = 0;
  for (const auto& s : labels) w = std::max(w, text_size(s, kText).width);
  return w;
}

/// The plot area and the ticks of a figure.
struct Frame {
  PlotGeometry g;
  Ticks xt, yt;
  std::vector<std::string> x_labels, y_labels;
};

int top_margin(const Axes& a) { return a.title.empty() ? kPad + 4 : 2 * kPad + kTextHeight; }
int bottom_margin(const Axes& a) {
  return kTickLength + 4 + kTextHeight + (a.x_label.empty() ? 0 : kPad + kTextHeight) + kPad;
}

/// Lay the figure out: y ticks (their labels set the left margin), then x ticks, thinned until
/// their labels do not touch. `right` is the right margin.
Frame make_frame(const Axes& a, Extent x, bool widen_x, Extent y, bool widen_y, int right) {
  const std::string name = quoted(a);
  Frame f;
  const int top = top_margin(a), bottom = a.height - 1 - bottom_margin(a);
  if (bottom - top < 40) throw std::invalid_argument("figure " + name + ": too small for its labels");
  f.yt = axis_ticks(y, a.y_min, a.y_max, widen_y, std::clamp((bottom - top) / 70, 3, 10), name, "y");
  f.y_labels = tick_labels(f.yt);
  const int left = kPad + (a.y_label.empty() ? 0 : kTextHeight + kPad) + widest(f.y_labels) + 4 + kTickLength + 2;
  const int right_px = a.width - 1 - right;
  if (right_px - left < 40) throw std::invalid_argument("figure " + name + ": too small for its labels");
  for (int target = std::clamp((right_px - left) / 110, 3, 10);; --target) {
    f.xt = axis_ticks(x, a.x_min, a.x_max, widen_x, target, name, "x");
    f.x_labels = tick_labels(f.xt);
    const double spacing = f.xt.step / (f.xt.hi - f.xt.lo) * (right_px - left);
    if (widest(f.x_labels) + 12 <= spacing || target <= 2) break;
  }
  f.g.area = {left, top, right_px, bottom};
  f.g.x_lo = f.xt.lo;
  f.g.x_hi = f.xt.hi;
  f.g.y_lo = f.yt.lo;
  f.g.y_hi = f.yt.hi;
  return f;
}

void draw_grid(Image& img, const Frame& f) {
  const PixelBox& a = f.g.area;
  for (double v : f.xt.values) fill_rect(img, f.g.column(v), a.top, f.g.column(v), a.bottom, kGridColour, a);
  for (double v : f.yt.values) fill_rect(img, a.left, f.g.row(v), a.right, f.g.row(v), kGridColour, a);
}

void draw_bold(Image& img, int x, int y, const std::string& s, int scale) {
  draw_text(img, x, y, s, kInk, scale);
  draw_text(img, x + 1, y, s, kInk, scale);
}

/// Frame, ticks, tick labels, axis labels and title (after the data, so they stay on top).
void draw_axes(Image& img, const Axes& ax, const Frame& f) {
  const PixelBox& a = f.g.area;
  const PixelBox all{0, 0, img.width() - 1, img.height() - 1};
  stroke_rect(img, a.left - 1, a.top - 1, a.right + 1, a.bottom + 1, kInk, all);
  for (std::size_t k = 0; k < f.xt.values.size(); ++k) {
    const int c = f.g.column(f.xt.values[k]);
    fill_rect(img, c, a.bottom + 2, c, a.bottom + 1 + kTickLength, kInk, all);
    const int w = text_size(f.x_labels[k], kText).width;
    draw_text(img, std::clamp(c - w / 2, 0, std::max(0, img.width() - w)), a.bottom + 2 + kTickLength + 4, f.x_labels[k], kInk, kText);
  }
  for (std::size_t k = 0; k < f.yt.values.size(); ++k) {
    const int r = f.g.row(f.yt.values[k]);
    fill_rect(img, a.left - 1 - kTickLength, r, a.left - 2, r, kInk, all);
    const int w = text_size(f.y_labels[k], kText).width;
    draw_text(img, a.left - 2 - kTickLength - 4 - w, r - kTextHeight / 2, f.y_labels[k], kInk, kText);
  }
  if (!ax.x_label.empty()) {
    const int w = text_size(ax.x_label, kText).width;
    draw_text(img, (a.left + a.right) / 2 - w / 2, img.height() - kPad - kTextHeight, ax.x_label, kInk, kText);
  }
  if (!ax.y_label.empty()) {
    const int h = text_size(ax.y_label, kText, TextDirection::up).height;
    draw_text(img, kPad, (a.top + a.bottom) / 2 - h / 2, ax.y_label, kInk, kText, TextDirection::up);
  }
  if (!ax.title.empty()) {
    // A title too long for the figure drops to the small font rather than being cut off.
    const int scale = text_size(ax.title, kText).width + 1 + 2 * kPad <= img.width() ? kText : 1;
    const int w = text_size(ax.title, scale).width + 1;
    const int x = std::clamp((a.left + a.right) / 2 - w / 2, 0, std::max(0, img.width() - w));
    draw_bold(img, x, kPad + (kTextHeight - kGlyphHeight * scale) / 2, ax.title, scale);
  }
}

struct LegendEntry {
  std::string name;
  Rgb colour;
  LineStyle line = LineStyle::none;
  Marker marker = Marker::none;
  bool swatch = false;  // a filled square (bars)
};

/// Top-left corner of a legend box of size w x h at `place` inside `area`.
std::pair<int, int> legend_corner(const PixelBox& area, LegendPlace place, int w, int h) {
  constexpr int kInset = 10;
  const int left = area.left + kInset, right = area.right - kInset - w, centre = (area.left + area.right - w) / 2;
  const int top = area.top + kInset, bottom = area.bottom - kInset - h;
  switch (place) {
    case LegendPlace::top_left: return {left, top};
    case LegendPlace::bottom_right: return {right, bottom};
    case LegendPlace::bottom_left: return {left, bottom};
    case LegendPlace::top_centre: return {centre, top};
    case LegendPlace::bottom_centre: return {centre, bottom};
    default: return {right, top};
  }
}

/// Pixels inside the box that are neither background nor grid: data the legend would hide.
int covered(const Image& img, int x0, int y0, int w, int h) {
  int n = 0;
  for (int y = std::max(0, y0); y <= std::min(img.height() - 1, y0 + h); ++y)
    for (int x = std::max(0, x0); x <= std::min(img.width() - 1, x0 + w); ++x) {
      const Rgb p = img.at(x, y);
      const bool blank = (p.r == kWhite.r && p.g == kWhite.g && p.b == kWhite.b) ||
                         (p.r == kGridColour.r && p.g == kGridColour.g && p.b == kGridColour.b);
      n += !blank;
    }
  return n;
}

constexpr int kLegendSample = 34, kLegendRow = kTextHeight + 8, kLegendPad = 8;

/// The legend box's width and height in pixels.
std::pair<int, int> legend_size(const std::vector<LegendEntry>& entries) {
  int text_w = 0;
  for (const auto& e : entries) text_w = std::max(text_w, text_size(e.name, kText).width);
  return {kLegendPad + kLegendSample + 8 + text_w + kLegendPad, 2 * kLegendPad + kLegendRow * static_cast<int>(entries.size()) - 8};
}

/// `best`: the first of the least-covered candidate places, in a fixed order (deterministic), and
/// how many data pixels it covers.
std::pair<LegendPlace, int> least_covered(const Image& img, const PixelBox& area, const std::vector<LegendEntry>& entries) {
  const auto [w, h] = legend_size(entries);
  LegendPlace place = LegendPlace::top_right;
  int least = -1;
  for (LegendPlace p : {LegendPlace::top_right, LegendPlace::top_left, LegendPlace::top_centre, LegendPlace::bottom_right,
                        LegendPlace::bottom_left, LegendPlace::bottom_centre}) {
    const auto [x, y] = legend_corner(area, p, w, h);
    const int n = covered(img, x, y, w, h);
    if (least < 0 || n < least) {
      least = n;
      place = p;
    }
  }
  return {place, least};
}

void draw_legend(Image& img, const PixelBox& area, LegendPlace place, const std::vector<LegendEntry>& entries) {
  if (place == LegendPlace::none || entries.empty()) return;
  const auto [w, h] = legend_size(entries);
  if (place == LegendPlace::best) place = least_covered(img, area, entries).first;
  const auto [x0, y0] = legend_corner(area, place, w, h);
  fill_rect(img, x0, y0, x0 + w, y0 + h, kWhite, area);
  stroke_rect(img, x0, y0, x0 + w, y0 + h, kLegendBorder, area);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const LegendEntry& e = entries[k];
    const int y = y0 + kLegendPad + static_cast<int>(k) * kLegendRow, cy = y + kTextHeight / 2;
    const int sx = x0 + kLegendPad;
    if (e.swatch) {
      fill_rect(img, sx + 8, cy - 7, sx + kLegendSample - 8, cy + 7, e.colour, area);
      stroke_rect(img, sx + 8, cy - 7, sx + kLegendSample - 8, cy + 7, kInk, area);
    }
    if (e.line != LineStyle::none) draw_line(img, sx, cy, sx + kLegendSample, cy, e.colour, 2, e.line == LineStyle::dashed, area);
    if (e.marker != Marker::none) draw_marker(img, e.marker, sx + kLegendSample / 2, cy, 4, e.colour, area);
    draw_text(img, sx + kLegendSample + 8, y, e.name, kInk, kText);
  }
}

bool increasing(const std::vector<double>& v) {
  for (std::size_t k = 0; k + 1 < v.size(); ++k)
    if (!(v[k] < v[k + 1]) || !std::isfinite(v[k]) || !std::isfinite(v[k + 1])) return false;
  return true;
}

/// Index of the interval of sorted `edges` (count + 1 values starting at `first`) holding `x`, or -1.
int find_interval(const std::vector<double>& edges, std::size_t first, std::size_t count, double x) {
  const auto b = edges.begin() + static_cast<std::ptrdiff_t>(first);
  const auto e = b + static_cast<std::ptrdiff_t>(count + 1);
  if (x < *b || x > *(e - 1)) return -1;
  const auto it = std::upper_bound(b, e, x);
  return std::min(static_cast<int>(it - b) - 1, static_cast<int>(count) - 1);
}

}  // namespace

int PlotGeometry::column(double x) const { return static_cast<int>(std::lround(u(x))); }
int PlotGeometry::row(double y) const { return static_cast<int>(std::lround(v(y))); }

Rgb palette(std::size_t index) { return kPalette[index % std::size(kPalette)]; }

Image draw(const LinePlot& p, PlotGeometry* geometry) {
  Extent x, y;
  for (const Series& s : p.series) {
    if (s.x.size() != s.y.size()) {
      throw std::invalid_argument("line plot " + quoted(p.axes) + ": series '" + s.name + "' has " +
                                  std::to_string(s.x.size()) + " x values but " + std::to_string(s.y.size()) + " y values");
    }
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k])) continue;
      x.add(s.x[k]);
      y.add(s.y[k]);
    }
  }
  if (x.empty()) throw std::invalid_argument("line plot " + quoted(p.axes) + ": nothing to plot (no finite points)");
  const Frame f = make_frame(p.axes, x, true, y, true, kPad + 8);
  Image img(p.axes.width, p.axes.height);
  draw_grid(img, f);
  std::vector<LegendEntry> legend;
  for (std::size_t n = 0; n < p.series.size(); ++n) {
    const Series& s = p.series[n];
    const Rgb colour = s.colour.value_or(palette(n));
    if (s.line != LineStyle::none) {
      for (std::size_t k = 0; k + 1 < s.x.size(); ++k) {
        if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k]) || !std::isfinite(s.x[k + 1]) || !std::isfinite(s.y[k + 1])) continue;
        draw_line(img, f.g.u(s.x[k]), f.g.v(s.y[k]), f.g.u(s.x[k + 1]), f.g.v(s.y[k + 1]), colour, s.width,
                  s.line == LineStyle::dashed, f.g.area);
      }
    }
    if (s.marker != Marker::none) {
      for (std::size_t k = 0; k < s.x.size(); ++k) {
        if (!std::isfinite(s.x[k]) || !std::isfinite(s.y[k])) continue;
        const double u = f.g.u(s.x[k]), v = f.g.v(s.y[k]);
        if (u < f.g.area.left - 10 || u > f.g.area.right + 10 || v < f.g.area.top - 10 || v > f.g.area.bottom + 10) continue;
        draw_marker(img, s.marker, f.g.column(s.x[k]), f.g.row(s.y[k]), 4, colour, f.g.area);
      }
    }
    if (!s.name.empty()) legend.push_back({s.name, colour, s.line, s.marker, false});
  }
  if (p.legend == LegendPlace::best && !legend.empty() && !p.axes.y_max && least_covered(img, f.g.area, legend).second > 0) {
    // Every place the legend could go hides data: draw again with the y axis raised by the legend's
    // height, so that a band above the data holds it (once: the raised axis is then fixed).
    const int area_h = f.g.area.bottom - f.g.area.top, band = legend_size(legend).second + 20;
    if (band < area_h / 2) {
      LinePlot raised = p;
      raised.axes.y_min = f.g.y_lo;
      raised.axes.y_max = f.g.y_lo + (f.g.y_hi - f.g.y_lo) * area_h / (area_h - band);
      return draw(raised, geometry);
    }
  }
  draw_legend(img, f.g.area, p.legend, legend);
  draw_axes(img, p.axes, f);
  if (geometry) *geometry = f.g;
  return img;
}

Image draw(const BarChart& c, PlotGeometry* geometry) {
  const std::string name = quoted(c.axes);
  if (c.edges.size() < 2 || !increasing(c.edges)) {
    throw std::invalid_argument("bar chart " + name + ": needs at least two increasing, finite bin edges");
  }
  const std::size_t bins = c.edges.size() - 1;
  Extent x, y;
  x.add(c.edges.front());
  x.add(c.edges.back());
  y.add(0.0);
  bool any = false;
  for (const BarSeries& s : c.series) {
    if (s.values.size() != bins) {
      throw std::invalid_argument("bar chart " + name + ": series '" + s.name + "' has " + std::to_string(s.values.size()) +
                                  " values for " + std::to_string(bins) + " bins");
    }
    for (double v : s.values) {
      if (std::isfinite(v)) any = true;
      y.add(v);
    }
  }
  if (!any) throw std::invalid_argument("bar chart " + name + ": nothing to plot (no finite values)");
  const Frame f = make_frame(c.axes, x, false, y, true, kPad + 8);
  Image img(c.axes.width, c.axes.height);
  draw_grid(img, f);
  const double base = std::clamp(0.0, f.g.y_lo, f.g.y_hi);
  const std::size_t m = c.series.size();
  std::vector<LegendEntry> legend;
  for (std::size_t n = 0; n < m; ++n) {
    const BarSeries& s = c.series[n];
    const Rgb colour = s.colour.value_or(palette(n));
    for (std::size_t b = 0; b < bins; ++b) {
      const double v = s.values[b];
      if (!std::isfinite(v)) continue;
      // Each bin keeps 10 % free on either side; its series share the rest.
      const double w = c.edges[b + 1] - c.edges[b];
      const double x0 = c.edges[b] + 0.1 * w + 0.8 * w * n / m, x1 = c.edges[b] + 0.1 * w + 0.8 * w * (n + 1) / m;
      const int px0 = f.g.column(x0), px1 = std::max(px0, f.g.column(x1) - 1);
      const int py0 = f.g.row(base), py1 = f.g.row(std::clamp(v, f.g.y_lo, f.g.y_hi));
      fill_rect(img, px0, py0, px1, py1, colour, f.g.area);
      if (px1 - px0 >= 3 && py0 != py1) stroke_rect(img, px0, py0, px1, py1, kInk, f.g.area);
    }
    if (!s.name.empty()) legend.push_back({s.name, colour, LineStyle::none, Marker::none, true});
  }
  draw_legend(img, f.g.area, c.legend, legend);
  draw_axes(img, c.axes, f);
  if (geometry) *geometry = f.g;
  return img;
}

Image draw(const HeatMap& h, PlotGeometry* geometry) {
  const std::string name = quoted(h.axes);
  if (h.x_edges.size() < 2 || !increasing(h.x_edges)) {
    throw std::invalid_argument("heat map " + name + ": needs at least two increasing, finite x edges");
  }
  const std::size_t nx = h.x_edges.size() - 1;
  std::size_t ny = 0;
  bool per_column = false;
  if (h.y_edges.size() >= 2 && increasing(h.y_edges)) {
    ny = h.y_edges.size() - 1;
  } else if (h.y_edges.size() % nx == 0 && h.y_edges.size() / nx >= 2) {
    per_column = true;
    ny = h.y_edges.size() / nx - 1;
    for (std::size_t i = 0; i < nx; ++i) {
      const std::vector<double> col(h.y_edges.begin() + static_cast<std::ptrdiff_t>(i * (ny + 1)),
                                    h.y_edges.begin() + static_cast<std::ptrdiff_t>((i + 1) * (ny + 1)));
      if (!increasing(col)) throw std::invalid_argument("heat map " + name + ": the y edges of column " + std::to_string(i) + " do not increase");
    }
  } else {
    throw std::invalid_argument("heat map " + name + ": y edges must be ny + 1 increasing values or nx (ny + 1) per column");
  }
  if (h.values.size() != nx * ny) {
    throw std::invalid_argument("heat map " + name + ": " + std::to_string(h.values.size()) + " values for " +
                                std::to_string(nx) + " x " + std::to_string(ny) + " cells");
  }
  Extent x, y, value;
  x.add(h.x_edges.front());
  x.add(h.x_edges.back());
  for (double e : h.y_edges) y.add(e);
  for (double v : h.values) value.add(v);
  if (value.empty()) throw std::invalid_argument("heat map " + name + ": nothing to plot (no finite values)");

  // Colour range and its ticks (the colour bar's labels set the right margin).
  Ticks vt;
  {
    Extent vr = value;
    if (h.map == ColourMap::diverging && !h.v_min && !h.v_max) {
      const double m = std::max(std::abs(value.lo), std::abs(value.hi));
      vr.lo = -m;
      vr.hi = m;
    }
    const bool fixed = h.v_min || h.v_max;
    vt = axis_ticks(vr, h.v_min, h.v_max, !fixed, 5, name, "colour");
  }
  const std::vector<std::string> v_labels = tick_labels(vt);
  const int right = kColourBarGap + kColourBarWidth + 4 + kTickLength + 4 + widest(v_labels) +
                    (h.value_label.empty() ? 0 : kPad + kTextHeight) + kPad;

  Axes axes = h.axes;
  Frame f = make_frame(axes, x, false, y, false, right);
  if (h.equal_aspect) {
    // Shrink the figure (not the data range) until a metre spans as many pixels along x as along
    // y; two passes, since the tick labels move the margins a little.
    for (int pass = 0; pass < 2; ++pass) {
      const double px_per_x = (f.g.area.right - f.g.area.left) / (f.g.x_hi - f.g.x_lo);
      const double px_per_y = (f.g.area.bottom - f.g.area.top) / (f.g.y_hi - f.g.y_lo);
      if (px_per_y > px_per_x) {
        axes.height -= static_cast<int>(std::lround((px_per_y - px_per_x) * (f.g.y_hi - f.g.y_lo)));
      } else {
        axes.width -= static_cast<int>(std::lround((px_per_x - px_per_y) * (f.g.x_hi - f.g.x_lo)));
      }
      f = make_frame(axes, x, false, y, false, right);
    }
  }
  Image img(axes.width, axes.height);
  const PixelBox& a = f.g.area;
  for (int py = a.top; py <= a.bottom; ++py) {
    const double yv = f.g.y_lo + (a.bottom - py) * (f.g.y_hi - f.g.y_lo) / (a.bottom - a.top);
    for (int px = a.left; px <= a.right; ++px) {
      const double xv = f.g.x_lo + (px - a.left) * (f.g.x_hi - f.g.x_lo) / (a.right - a.left);
      const int i = find_interval(h.x_edges, 0, nx, xv);
      if (i < 0) continue;
      const int j = find_interval(h.y_edges, per_column ? static_cast<std::size_t>(i) * (ny + 1) : 0, ny, yv);
      if (j < 0) continue;
      const double val = h.values[static_cast<std::size_t>(j) * nx + static_cast<std::size_t>(i)];
      img.at(px, py) = colour_at(h.map, std::isfinite(val) ? (val - vt.lo) / (vt.hi - vt.lo) : std::nan(""));
    }
  }
  // Colour bar: same height as the plot area, its own ticks on the right.
  const PixelBox all{0, 0, img.width() - 1, img.height() - 1};
  const int bx0 = a.right + 1 + kColourBarGap, bx1 = bx0 + kColourBarWidth - 1;
  for (int py = a.top; py <= a.bottom; ++py) {
    fill_rect(img, bx0, py, bx1, py, colour_at(h.map, static_cast<double>(a.bottom - py) / (a.bottom - a.top)), all);
  }
  stroke_rect(img, bx0 - 1, a.top - 1, bx1 + 1, a.bottom + 1, kInk, all);
  for (std::size_t k = 0; k < vt.values.size(); ++k) {
    const int r = static_cast<int>(std::lround(a.bottom - (vt.values[k] - vt.lo) / (vt.hi - vt.lo) * (a.bottom - a.top)));
    fill_rect(img, bx1 + 2, r, bx1 + 1 + kTickLength, r, kInk, all);
    draw_text(img, bx1 + 2 + kTickLength + 4, r - kTextHeight / 2, v_labels[k], kInk, kText);
  }
  if (!h.value_label.empty()) {
    const int th = text_size(h.value_label, kText, TextDirection::up).height;
    draw_text(img, img.width() - kPad - kTextHeight, (a.top + a.bottom) / 2 - th / 2, h.value_label, kInk, kText,
              TextDirection::up);
  }
  draw_axes(img, axes, f);
  if (geometry) *geometry = f.g;
  return img;
}

std::vector<double> histogram(const std::vector<double>& values, const std::vector<double>& edges) {
  if (edges.size() < 2 || !increasing(edges)) throw std::invalid_argument("histogram: needs at least two increasing bin edges");
  std::vector<double> counts(edges.size() - 1, 0.0);
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    const int k = find_interval(edges, 0, counts.size(), v);
    if (k >= 0) counts[static_cast<std::size_t>(k)] += 1;
  }
  return counts;
}

}  // namespace grainscale::studies
