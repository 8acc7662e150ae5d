#pragma once
// Figures of a coarse-graining run (`grainscale cg`), written beside its numbers in the output
// folder and read back from its CSV files (docs/coarsegrain_layout.md, docs/plots.md):
//
//   slices.png         chaff per slice (% of all chaff), first vs last snapshot with chaff: the
//                      report's Figure 11 (bars)
//   coverage.png       top-view chaff coverage per slice along x, first vs last, with what the
//                      report measured on photographs of wheat after 30 min: about 10 % in the
//                      centre and 60 % at the ends
//   congregation.png   congregation index of each end over time (1: uniform mixture)
//   concentration.png  chaff volume concentration c(x, z) of the last frame (heat map; 2-D and
//                      3-D grids, averaged over y)
//
// The figure builders are separate from the writing so tests can check what a figure shows.
#include <ostream>
#include <string>
#include <vector>

#include "studies/numeric_csv.hpp"
#include "studies/plot.hpp"

namespace grainscale::studies {

/// The report's top-view measurement (SAGIT USA120; shared/data/source_measurements.yaml,
/// measured_outcomes.wheat_surface_chaff_pixel_fraction) and the end zone it is compared over
/// (the report's "right hand 100mm"; the congregation index's default end_length).
constexpr double kReportCoverageCentre = 0.10, kReportCoverageEnds = 0.60, kReportEndZone = 0.1;

BarChart slices_figure(const NumericCsv& slices);            // slices.csv
LinePlot coverage_figure(const NumericCsv& coverage);        // coverage.csv
LinePlot congregation_figure(const NumericCsv& congregation);  // congregation.csv
HeatMap concentration_figure(const NumericCsv& fields);      // fields.csv (t_s, x_m, z_m, c)

struct CgPlotReport {
  std::vector<std::string> written;  // paths
  std::vector<std::string> skipped;  // "figure: reason"
};

/// Write the figures into `output_dir`. A figure whose file is missing or holds nothing to plot is
/// skipped with its reason, never thrown: the run's numbers are already written and stay valid.
/// One line per figure goes to `log` ("plot: PATH" or "no plot NAME: REASON").
CgPlotReport write_cg_plots(const std::string& output_dir, std::ostream& log);

}  // namespace grainscale::studies
