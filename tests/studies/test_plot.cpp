// Plots: data land on the pixels the geometry says, figures are byte-identical when redrawn, and
// bad data (NaN, nothing finite, mismatched lengths) is skipped or refused with a clear message.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "studies/plot.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::studies;

namespace {

bool same(Rgb a, Rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }
const Rgb kRed{255, 0, 0}, kWhite{255, 255, 255};
const double kNaN = std::numeric_limits<double>::quiet_NaN();

LinePlot two_series() {
  LinePlot p;
  p.axes.title = "Coverage along the box";
  p.axes.x_label = "x (m)";
  p.axes.y_label = "coverage";
  p.series.push_back({"first", {0.0, 0.2, 0.4, 0.6, 0.8}, {0.3, 0.25, 0.2, 0.3, 0.5}});
  p.series.push_back({"last", {0.0, 0.2, 0.4, 0.6, 0.8}, {0.6, 0.1, 0.1, 0.2, 0.6}, LineStyle::dashed, Marker::circle});
  return p;
}

}  // namespace

TEST_CASE("A plotted point lands on the pixel its coordinates map to", "[studies][plot]") {
  LinePlot p;
  p.series.push_back({"", {0.0, 1.0}, {0.0, 1.0}, LineStyle::none, Marker::none});
  p.series.push_back({"", {0.5}, {0.25}, LineStyle::none, Marker::square, kRed});
  PlotGeometry g;
  const Image img = draw(p, &g);
  // The data [0, 1] x [0, 1] are already on whole steps: the axes end exactly there.
  CHECK(g.x_lo == 0.0);
  CHECK(g.x_hi == 1.0);
  CHECK(g.y_lo == 0.0);
  CHECK(g.y_hi == 1.0);
  const int cx = static_cast<int>(std::lround(g.area.left + 0.5 * (g.area.right - g.area.left)));
  const int cy = static_cast<int>(std::lround(g.area.bottom - 0.25 * (g.area.bottom - g.area.top)));
  CHECK(g.column(0.5) == cx);
  CHECK(g.row(0.25) == cy);
  CHECK(same(img.at(cx, cy), kRed));
  CHECK(same(img.at(cx + 3, cy - 3), kRed));   // the square marker around it
  CHECK(!same(img.at(cx + 6, cy), kRed));      // and no further
  CHECK(!same(img.at(cx, cy + 6), kRed));

  // With fixed limits x in [0, 2], y in [-1, 1], the point (1, 0) is the area's centre.
  LinePlot q;
  q.axes.x_min = 0;
  q.axes.x_max = 2;
  q.axes.y_min = -1;
  q.axes.y_max = 1;
  q.series.push_back({"", {1.0}, {0.0}, LineStyle::none, Marker::diamond, kRed});
  const Image qi = draw(q, &g);
  CHECK(g.x_lo == 0.0);
  CHECK(g.x_hi == 2.0);
  CHECK(same(qi.at((g.area.left + g.area.right + 1) / 2, (g.area.top + g.area.bottom + 1) / 2), kRed));
}

TEST_CASE("A horizontal line covers its row across the plot area and stops at the frame", "[studies][plot]") {
  LinePlot p;
  p.axes.x_min = -5;
  p.axes.x_max = 5;
  p.axes.y_min = 0;
  p.axes.y_max = 1;
  // Ends far outside the axes: clipped, not rasterised over a million pixels.
  p.series.push_back({"", {-5e6, 5e6}, {0.5, 0.5}, LineStyle::solid, Marker::none, kRed, 1});
  PlotGeometry g;
  const Image img = draw(p, &g);
  const int r = g.row(0.5);
  for (int x = g.area.left; x <= g.area.right; ++x) CHECK(same(img.at(x, r), kRed));
  CHECK(!same(img.at(g.area.left - 1, r), kRed));   // the frame
  CHECK(!same(img.at(g.area.right + 2, r), kRed));  // outside the area
  CHECK(!same(img.at(g.area.left + 5, r - 1), kRed));  // one pixel wide
}

TEST_CASE("Bars rise from zero to their value", "[studies][plot]") {
  BarChart c;
  c.axes.title = "Chaff per slice";
  c.edges = {0.0, 0.05, 0.10, 0.15};
  c.series.push_back({"final", {10.0, kNaN, 40.0}, kRed});
  PlotGeometry g;
  const Image img = draw(c, &g);
  CHECK(g.y_lo == 0.0);
  CHECK(g.y_hi >= 40.0);
  const int x = g.column(0.125);
  CHECK(same(img.at(x, g.row(20.0)), kRed));
  CHECK(!same(img.at(x, g.row(40.0) - 2), kRed));
  // The NaN bin has no bar.
  CHECK(!same(img.at(g.column(0.075), g.row(5.0)), kRed));
  // Bin 0 stops at 10.
  CHECK(same(img.at(g.column(0.025), g.row(5.0)), kRed));
  CHECK(!same(img.at(g.column(0.025), g.row(12.0)), kRed));
}

TEST_CASE("Heat map cells take the colour of their value; NaN is grey, no cell is white", "[studies][plot]") {
  HeatMap h;
  h.axes.title = "c(x, z)";
  h.x_edges = {0.0, 1.0, 2.0};
  // Per-column edges: column 0 spans z in [0, 1], column 1 only [0, 0.5] (a lower surface).
  h.y_edges = {0.0, 0.5, 1.0, 0.0, 0.25, 0.5};
  h.values = {0.0, 1.0, kNaN, 0.5};  // (i, j): (0,0)=0, (1,0)=1, (0,1)=NaN, (1,1)=0.5
  h.v_min = 0;
  h.v_max = 1;
  h.value_label = "c (-)";
  PlotGeometry g;
  const Image img = draw(h, &g);
  CHECK(same(img.at(g.column(0.5), g.row(0.25)), colour_at(ColourMap::sequential, 0.0)));
  CHECK(same(img.at(g.column(1.5), g.row(0.1)), colour_at(ColourMap::sequential, 1.0)));
  CHECK(same(img.at(g.column(1.5), g.row(0.4)), colour_at(ColourMap::sequential, 0.5)));
  CHECK(same(img.at(g.column(0.5), g.row(0.75)), kNoDataColour));
  CHECK(same(img.at(g.column(1.5), g.row(0.8)), kWhite));  // above column 1's surface
  // The colour map itself: dark to light, and the diverging map is light at its centre.
  const Rgb lo = colour_at(ColourMap::sequential, 0), hi = colour_at(ColourMap::sequential, 1);
  CHECK(lo.r + lo.g + lo.b < hi.r + hi.g + hi.b);
  const Rgb mid = colour_at(ColourMap::diverging, 0.5);
  CHECK(mid.r + mid.g + mid.b > 3 * 230);
}

TEST_CASE("Equal aspect makes a metre the same number of pixels along x and y", "[studies][plot]") {
  HeatMap h;
  h.x_edges = {0.0, 0.4, 0.8};
  h.y_edges = {0.0, 0.1, 0.2};
  h.values = {0.1, 0.2, 0.3, 0.4};
  h.equal_aspect = true;
  PlotGeometry g;
  const Image img = draw(h, &g);
  const double px_x = (g.area.right - g.area.left) / 0.8, px_y = (g.area.bottom - g.area.top) / 0.2;
  CHECK(px_x == Approx(px_y).epsilon(0.03));
  CHECK(img.height() < 600);
}

TEST_CASE("Figures redraw byte for byte", "[studies][plot]") {
  const LinePlot p = two_series();
  CHECK(draw(p).encode_png() == draw(p).encode_png());
  LinePlot changed = two_series();
  changed.series[1].y[2] = 0.11;
  CHECK(draw(changed).encode_png() != draw(p).encode_png());

  BarChart c;
  c.edges = {0, 1, 2, 3};
  c.series = {{"initial", {1, 2, 3}}, {"final", {3, 2, 1}}};
  CHECK(draw(c).encode_png() == draw(c).encode_png());

  HeatMap h;
  h.x_edges = {0, 1, 2, 3};
  h.y_edges = {0, 1};
  h.values = {-0.1, 0.0, 0.2};
  h.map = ColourMap::diverging;
  CHECK(draw(h).encode_png() == draw(h).encode_png());

  const grainscale::testing::TempDir tmp("test_plot");  // removed at the end, whatever the checks say
  const std::string path = tmp / "plot.png";
  draw(p).write_png(path);
  CHECK(std::filesystem::file_size(path) == draw(p).encode_png().size());
}

TEST_CASE("NaN points are skipped; nothing to plot is an error that names the figure", "[studies][plot]") {
  LinePlot p = two_series();
  p.series[0].y[2] = kNaN;
  p.series[1].x[0] = std::numeric_limits<double>::infinity();
  PlotGeometry g;
  REQUIRE_NOTHROW(draw(p, &g));
  CHECK(g.x_hi == Approx(0.8));

  LinePlot empty;
  empty.axes.title = "Empty";
  CHECK_THROWS_WITH(draw(empty), Catch::Contains("'Empty'") && Catch::Contains("nothing to plot"));
  empty.series.push_back({"all NaN", {kNaN, 1.0}, {1.0, kNaN}});
  empty.series.push_back({"no points", {}, {}});
  CHECK_THROWS_AS(draw(empty), std::invalid_argument);
  LinePlot mismatched;
  mismatched.series.push_back({"bad", {1, 2, 3}, {1, 2}});
  CHECK_THROWS_WITH(draw(mismatched), Catch::Contains("'bad'") && Catch::Contains("3 x values but 2 y values"));
  LinePlot bad_limits = two_series();
  bad_limits.axes.x_min = 1;
  bad_limits.axes.x_max = 1;
  CHECK_THROWS_AS(draw(bad_limits), std::invalid_argument);
  LinePlot tiny = two_series();
  tiny.axes.height = 60;
  CHECK_THROWS_WITH(draw(tiny), Catch::Contains("too small"));

  BarChart c;
  c.edges = {0, 1, 2};
  c.series = {{"nan", {kNaN, kNaN}}};
  CHECK_THROWS_WITH(draw(c), Catch::Contains("nothing to plot"));
  c.series = {{"short", {1.0}}};
  CHECK_THROWS_WITH(draw(c), Catch::Contains("1 values for 2 bins"));
  c.edges = {0, 2, 1};
  CHECK_THROWS_AS(draw(c), std::invalid_argument);

  HeatMap h;
  h.x_edges = {0, 1, 2};
  h.y_edges = {0, 1};
  h.values = {kNaN, kNaN};
  CHECK_THROWS_WITH(draw(h), Catch::Contains("nothing to plot"));
  h.values = {1.0};
  CHECK_THROWS_WITH(draw(h), Catch::Contains("1 values for 2 x 1 cells"));
}

TEST_CASE("Histogram counts finite values per bin, the last bin closed", "[studies][plot]") {
  const auto n = histogram({0.0, 0.5, 1.0, 1.5, 2.0, 2.5, kNaN, -1.0}, {0.0, 1.0, 2.0});
  CHECK(n == std::vector<double>{2, 3});
  CHECK_THROWS_AS(histogram({1.0}, {1.0}), std::invalid_argument);
}

TEST_CASE("A legend that would hide data in every place gets a band of its own above the data", "[studies][plot]") {
  // Red lines across the whole plot every 0.1 in y: every corner and both centres hold data. The y
  // axis is raised so that the legend sits above the top line and no red pixel is covered; the data
  // keep their x axis and the bottom of their y axis.
  LinePlot p;
  for (int k = 0; k <= 10; ++k) {
    p.series.push_back({k == 0 ? "one of eleven red lines across the plot" : "", {0.0, 1.0}, {0.1 * k, 0.1 * k},
                        LineStyle::solid, Marker::none, kRed, 3});
  }
  p.series.push_back({"a second entry", {0.5}, {0.5}, LineStyle::none, Marker::circle, kRed});
  PlotGeometry g;
  const Image img = draw(p, &g);
  CHECK(g.y_lo == 0.0);
  CHECK(g.y_hi > 1.1);  // raised
  CHECK(g.x_lo == 0.0);
  CHECK(g.x_hi == 1.0);
  // Every line is drawn whole: red across its row, nothing drawn over it.
  for (int k = 0; k <= 10; ++k) {
    const int row = g.row(0.1 * k);
    int red = 0;
    for (int x = g.column(0.0); x <= g.column(1.0); ++x) red += same(img.at(x, row), kRed);
    CAPTURE(k);
    CHECK(red == g.column(1.0) - g.column(0.0) + 1);
  }
  // A fixed y axis is kept as given: the legend then covers what it must.
  p.axes.y_max = 1.0;
  draw(p, &g);
  CHECK(g.y_hi == 1.0);
}
