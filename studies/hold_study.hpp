#pragma once
// `kind: hold` studies (docs/studies.md): the hold scenarios of issue 8 run one after the other through
// the `grainscale hold` driver (hold_run.hpp, hold_output.hpp), each into its own subfolder, then one
// report.md comparing them (hold_study_report.hpp): chaff build-up near each end wall over time, where
// a spear finds dirty grain, the figures each run wrote, a ranking by predicted congregation, the wall
// clock of each (issue 8: one day of rolling in <= 10 min on 2 cores) and the limits.
//
// Congregation is ranked by the end enrichment E = (share of all chaff in the top `top_layer` within
// `end_zone` of a wall) / (the same share for uniformly mixed chaff), the larger end's: 1 for no
// congregation, independent of the scenario's size, so a ship's hold and a truck compare.
#include <optional>
#include <string>
#include <vector>

#include "studies/closure_dem_comparison.hpp"
#include "studies/hold_study_settings.hpp"
#include "studies/study_run.hpp"

namespace grainscale::studies {

/// What the report needs from one scenario's run.
struct HoldScenarioOutcome {
  std::string name, file, folder;  // folder: relative to the study folder
  std::string what;                // container and motion in words
  double t_end = 0, file_end = 0, chunk = 0;
  bool shortened = false, compare_with_report = false, averaged = false;
  double wall_seconds = 0;
  long resolved_chunks = 0, total_chunks = 0, closure_steps = 0, chaff_steps = 0;
  double chaff_relative_change = 0, c_min = 0, c_max = 0, c_initial = 0;
  double top_layer = 0, end_zone = 0, spear_depth = 0, dirty_factor = 0, length = 0;
  // Over the output times (the first is t = 0):
  std::vector<double> times;
  std::vector<double> left_share, right_share;  // share of all chaff in the top layer near each end
  std::vector<double> surface_left, surface_right, surface_centre;  // mean top-cell c: end zones, centre zone
  double uniform_left = 0, uniform_right = 0;   // the shares for uniform chaff
  // At the end:
  double enrichment_left = 0, enrichment_right = 0;  // share / uniform share
  double spear_max = 0;                              // largest spear mean [-]
  std::vector<std::pair<double, double>> dirty;      // x intervals where a spear finds dirty grain [m]
  double visible_ratio_left = 0, visible_ratio_right = 0;  // chaff in the top grain diameter, end / centre
  std::vector<std::string> figures;                  // relative to the study folder
  double enrichment() const { return std::max(enrichment_left, enrichment_right); }
};

struct HoldStudyResults {
  std::vector<HoldScenarioOutcome> scenarios;  // in the study file's order
  std::vector<std::string> warnings;
  std::optional<ClosureDemComparison> validation;
  double wall_seconds = 0;
};

/// Runs every scenario into `<output>/<scenario name>/` and writes report.md; returns the results.
/// The study folder (inputs/, log.txt) is written through StudyFolder.
HoldStudyResults run_hold_study(const HoldStudySettings& s, const StudyOptions& options, std::string& report_path);

/// The study_kinds.cpp runner: reads the file, runs, returns the report's path.
std::string hold_study_runner(const std::string& study_file, const StudyOptions& options);

}  // namespace grainscale::studies
