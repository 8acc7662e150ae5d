#pragma once
// Figures for the studies, so every result can be looked at before its numbers are read: line
// plots, bar charts (and histograms) and heat maps. Each has a title, a framed plot area with
// light grid lines, ticks at nice numbers with labels, and axis labels, drawn with the built-in
// font onto an Image (write it with Image::write_png). Same input, same bytes.
//
// Bad data: NaN and infinite points are skipped (a line breaks there, so NaN can also separate
// segments within one series); a figure with nothing finite to draw throws std::invalid_argument
// naming the figure, as do mismatched lengths and decreasing edges.
#include <optional>
#include <string>
#include <vector>

#include "studies/colour_map.hpp"
#include "studies/png_image.hpp"
#include "studies/raster.hpp"

namespace grainscale::studies {

/// What every figure has.
struct Axes {
  std::string title, x_label, y_label;
  /// Fixed axis limits; an absent one comes from the data (line and bar plots round it outwards to
  /// the next tick).
  std::optional<double> x_min{}, x_max{}, y_min{}, y_max{};
  int width = 900, height = 600;  // pixels
};

enum class LineStyle { none, solid, dashed };
/// `best`: the candidate place (corners, top and bottom centre) covering the fewest drawn data pixels.
enum class LegendPlace { best, top_right, top_left, bottom_right, bottom_left, top_centre, bottom_centre, none };

struct Series {
  std::string name;  // legend entry; empty: not listed
  std::vector<double> x, y;
  LineStyle line = LineStyle::solid;
  Marker marker = Marker::none;
  std::optional<Rgb> colour{};  // default: the palette, by series position
  int width = 2;              // line width, pixels
};

struct LinePlot {
  Axes axes;
  std::vector<Series> series;
  LegendPlace legend = LegendPlace::best;
};

struct BarSeries {
  std::string name;
  std::vector<double> values;  // one per bin; NaN: no bar
  std::optional<Rgb> colour{};  // default: the palette
};

/// Bars over numeric bins on the x axis (histograms, per-slice values). Several series share each
/// bin side by side. Bars start at 0.
struct BarChart {
  Axes axes;
  std::vector<double> edges;  // n + 1 increasing bin edges
  std::vector<BarSeries> series;
  LegendPlace legend = LegendPlace::best;
};

/// A 2-D field on cells with a colour bar. Cells are [x_edges[i], x_edges[i+1]] x
/// [y_edges[j], y_edges[j+1]]; for terrain-following grids each column may have its own y edges.
/// Pixels with no cell are left white; cells with a NaN value are grey.
struct HeatMap {
  Axes axes;
  std::vector<double> x_edges;  // nx + 1, increasing
  std::vector<double> y_edges;  // ny + 1 shared by all columns, or nx * (ny + 1) (column i at i * (ny + 1))
  std::vector<double> values;   // nx * ny, x fastest: values[j * nx + i]
  std::string value_label;      // beside the colour bar
  std::optional<double> v_min, v_max;  // colour range; default: the data's (diverging: symmetric about 0)
  ColourMap map = ColourMap::sequential;
  bool equal_aspect = false;  // one metre is as many pixels along x as along y (the figure shrinks to fit)
};

/// Where data land in a drawn figure (for tests and for drawing on top of it).
struct PlotGeometry {
  PixelBox area;                  // the plot area, inside the frame
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;  // axis limits at the area's outer pixel centres
  /// Continuous pixel coordinates: x_lo is the centre of pixel column area.left, x_hi of area.right.
  double u(double x) const { return area.left + (x - x_lo) / (x_hi - x_lo) * (area.right - area.left); }
  double v(double y) const { return area.bottom - (y - y_lo) / (y_hi - y_lo) * (area.bottom - area.top); }
  /// The pixel a data point lands on.
  int column(double x) const;
  int row(double y) const;
};

Image draw(const LinePlot& plot, PlotGeometry* geometry = nullptr);
Image draw(const BarChart& chart, PlotGeometry* geometry = nullptr);
Image draw(const HeatMap& map, PlotGeometry* geometry = nullptr);

/// Counts of the finite `values` in the bins `edges` (n + 1 increasing); the last bin includes its
/// right edge, values outside are not counted.
std::vector<double> histogram(const std::vector<double>& values, const std::vector<double>& edges);

/// The default colours of series 0, 1, 2, ... (repeating after eight).
Rgb palette(std::size_t index);

}  // namespace grainscale::studies
