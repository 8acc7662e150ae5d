// Figures of a cg output folder: they show the right snapshots (the first with chaff, the last),
// the report's measured coverage, and c(x, z) of the last frame; missing or empty files are
// skipped with a reason, never thrown; redrawing gives the same bytes.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dem/input_error.hpp"
#include "studies/cg_plots.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale;
using namespace grainscale::studies;
namespace fs = std::filesystem;

namespace {

// Three snapshots over four 0.2 m slices of a 0.8 m box; the first (t = 0) has no particles.
const char* kSlices =
    "t_s,x_m,chaff_percent,x_lo_m,x_hi_m,chaff_bodies,grain_bodies,c_number,c_volume\n"
    "0,0.1,nan,0,0.2,0,0,nan,nan\n0,0.3,nan,0.2,0.4,0,0,nan,nan\n0,0.5,nan,0.4,0.6,0,0,nan,nan\n0,0.7,nan,0.6,0.8,0,0,nan,nan\n"
    "1,0.1,25,0,0.2,5,50,0.1,0.2\n1,0.3,25,0.2,0.4,5,50,0.1,0.2\n1,0.5,25,0.4,0.6,5,50,0.1,0.2\n1,0.7,25,0.6,0.8,5,50,0.1,0.2\n"
    "2,0.1,10,0,0.2,2,50,0.04,0.1\n2,0.3,5,0.2,0.4,1,50,0.02,0.1\n2,0.5,5,0.4,0.6,1,50,0.02,0.1\n2,0.7,80,0.6,0.8,16,50,0.3,0.5\n";
const char* kCoverage =
    "t_s,x_m,coverage,x_lo_m,x_hi_m,occupied_pixels,chaff_pixels\n"
    "0,0.1,nan,0,0.2,0,0\n0,0.3,nan,0.2,0.4,0,0\n0,0.5,nan,0.4,0.6,0,0\n0,0.7,nan,0.6,0.8,0,0\n"
    "1,0.1,0.3,0,0.2,100,30\n1,0.3,0.3,0.2,0.4,100,30\n1,0.5,0.3,0.4,0.6,100,30\n1,0.7,0.3,0.6,0.8,100,30\n"
    "2,0.1,0.5,0,0.2,100,50\n2,0.3,0.1,0.2,0.4,100,10\n2,0.5,0.1,0.4,0.6,100,10\n2,0.7,0.6,0.6,0.8,100,60\n";
const char* kCongregation =
    "t_s,index_left,index_right,index_mean,index_spread,share_left,share_right,coverage_left,coverage_centre,"
    "coverage_right,coverage_ratio,coverage\n"
    "0,nan,nan,nan,nan,nan,nan,nan,nan,nan,nan,nan\n1,1,1,1,0,1,1,0.3,0.3,0.3,1,0.3\n2,0.8,3.2,2,1.2,1,1,0.5,0.1,0.6,5.5,0.3\n";

/// fields.csv of a 3-D grid 2 (x) x 2 (y) x 2 (z) over two frames.
std::string fields_csv() {
  std::ostringstream s;
  s << "t_s,x_m,z_m,c,y_m,phi\n";
  for (double t : {0.0, 2.0})
    for (double z : {0.025, 0.075})
      for (double y : {0.05, 0.15})
        for (double x : {0.2, 0.6}) {
          double c = t + x + 10 * z + y;  // distinct per cell and frame
          if (t == 2.0 && z == 0.075 && x == 0.6) c = std::nan("");  // no particles there
          if (t == 2.0 && z == 0.025 && x == 0.2 && y == 0.15) c = std::nan("");  // one y empty: mean of the other
          s << t << "," << x << "," << z << "," << c << "," << y << ",0.6\n";
        }
  return s.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("Slice bars compare the first snapshot with chaff to the last", "[studies][cg_plots]") {
  const BarChart c = slices_figure(NumericCsv::parse(kSlices, "slices.csv"));
  CHECK(c.edges == std::vector<double>{0, 0.2, 0.4, 0.6, 0.8});
  REQUIRE(c.series.size() == 2);
  CHECK(c.series[0].name == "initial, t = 1 s");  // t = 0 had no chaff
  CHECK(c.series[0].values == std::vector<double>{25, 25, 25, 25});
  CHECK(c.series[1].name == "final, t = 2 s");
  CHECK(c.series[1].values == std::vector<double>{10, 5, 5, 80});
  CHECK(c.axes.title.find("200 mm slice") != std::string::npos);
}

TEST_CASE("Coverage profile carries the report's 60 % ends and 10 % centre", "[studies][cg_plots]") {
  const LinePlot p = coverage_figure(NumericCsv::parse(kCoverage, "coverage.csv"));
  REQUIRE(p.series.size() == 4);
  CHECK(p.series[0].y == std::vector<double>{30, 30, 30, 30});  // percent
  CHECK(p.series[1].y == std::vector<double>{50, 10, 10, 60});
  const Series& ends = p.series[2];
  CHECK(ends.x[0] == 0.0);
  CHECK(ends.x[1] == Approx(kReportEndZone));
  CHECK(ends.x[4] == 0.8);
  CHECK(ends.x[3] == Approx(0.8 - kReportEndZone));
  CHECK(std::isnan(ends.y[2]));  // two segments
  CHECK(ends.y[0] == Approx(60));
  const Series& centre = p.series[3];
  CHECK(centre.y[0] == Approx(10));
  CHECK(0.5 * (centre.x[0] + centre.x[1]) == Approx(0.4));
}

TEST_CASE("Congregation index over time with the uniform level from the first finite time", "[studies][cg_plots]") {
  const LinePlot p = congregation_figure(NumericCsv::parse(kCongregation, "congregation.csv"));
  REQUIRE(p.series.size() == 3);
  CHECK(p.series[1].y[2] == 3.2);
  CHECK(p.series[2].x == std::vector<double>{1, 2});
  CHECK(p.series[2].y == std::vector<double>{1, 1});
  CHECK_THROWS_AS(congregation_figure(NumericCsv::parse("t_s,index_left,index_right\n0,nan,nan\n", "c.csv")), InputError);
}

TEST_CASE("Concentration map shows the last frame, averaged over y", "[studies][cg_plots]") {
  const HeatMap h = concentration_figure(NumericCsv::parse(fields_csv(), "fields.csv"));
  REQUIRE(h.x_edges.size() == 3);
  CHECK(h.x_edges[0] == Approx(0.0).margin(1e-15));
  CHECK(h.x_edges[1] == Approx(0.4));
  CHECK(h.x_edges[2] == Approx(0.8));
  REQUIRE(h.y_edges.size() == 3);
  CHECK(h.y_edges[0] == Approx(0.0).margin(1e-15));
  CHECK(h.y_edges[2] == Approx(0.1));
  REQUIRE(h.values.size() == 4);
  CHECK(h.values[0] == Approx(2 + 0.2 + 0.25 + 0.05));           // (x 0.2, z 0.025): only y = 0.05 has chaff data
  CHECK(h.values[1] == Approx(2 + 0.6 + 0.25 + 0.1));            // mean over y of 0.05 and 0.15
  CHECK(h.values[2] == Approx(2 + 0.2 + 0.75 + 0.1));
  CHECK(std::isnan(h.values[3]));
  CHECK(h.axes.title.find("t = 2 s") != std::string::npos);
  // A 1-D grid (one height) has nothing to map.
  CHECK_THROWS_WITH(concentration_figure(NumericCsv::parse("t_s,x_m,z_m,c\n0,0.1,0.1,0.2\n0,0.3,0.1,0.3\n", "f.csv")),
                    Catch::Contains("1-D"));
}

TEST_CASE("write_cg_plots writes four PNGs, the same bytes twice, and skips what is missing", "[studies][cg_plots]") {
  // A fresh folder (mkdtemp), removed at the end even when a check fails.
  const grainscale::testing::TempDir tmp("test_cg_plots");
  const fs::path& dir = tmp.path;
  write(dir / "slices.csv", kSlices);
  write(dir / "coverage.csv", kCoverage);
  write(dir / "congregation.csv", kCongregation);
  write(dir / "fields.csv", fields_csv());
  std::ostringstream log;
  const CgPlotReport r = write_cg_plots(dir.string(), log);
  CHECK(r.skipped.empty());
  REQUIRE(r.written.size() == 4);
  std::vector<std::string> first;
  for (const auto& p : r.written) {
    const std::string b = bytes(p);
    CHECK(b.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
    first.push_back(b);
  }
  CHECK(log.str().find("plot: ") != std::string::npos);
  const CgPlotReport again = write_cg_plots(dir.string(), log);
  for (std::size_t k = 0; k < again.written.size(); ++k) CHECK(bytes(again.written[k]) == first[k]);

  // Missing and empty files: skipped with reasons, the rest still drawn, nothing thrown.
  fs::remove(dir / "fields.csv");
  write(dir / "coverage.csv", "t_s,x_m,coverage,x_lo_m,x_hi_m\n0,0.1,nan,0,0.2\n");
  std::ostringstream log2;
  CgPlotReport partial;
  REQUIRE_NOTHROW(partial = write_cg_plots(dir.string(), log2));
  CHECK(partial.written.size() == 2);
  REQUIRE(partial.skipped.size() == 2);
  CHECK(partial.skipped[0].find("coverage.png") == 0);
  CHECK(partial.skipped[0].find("no finite value") != std::string::npos);
  CHECK(partial.skipped[1].find("fields.csv") != std::string::npos);
  CHECK(log2.str().find("no plot concentration.png") != std::string::npos);
}
