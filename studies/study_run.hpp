#pragma once
// `grainscale study FILE.yaml`: one study end to end, read as the algorithm -
//   setup();      output folder, inputs copied, log.txt opened
//   run();        dem();          the DEM scenario                          -> dem/
//                 coarse_grain(); fields and the report's measures          -> cg/  (+ cg_flow/: the flow)
//                 fit();          continuum coefficients fitted to cg/      -> fit/
//                 predict();      the fitted model run to the study's end   -> predict/
//   output();     report.md: what was run, figures, numbers, comparison with the measurements
// Each stage is driven by an ordinary stage file written into stages/ (with the paths between the
// stages filled in), so `grainscale cg|fit|predict stages/X.yaml` repeats any stage alone.
// Layout of the folder and keys of the study file: docs/studies.md.
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "studies/study_folder.hpp"
#include "studies/study_settings.hpp"

namespace grainscale::studies {

struct StudyOptions {
  std::string output_override;  // replaces output.directory if not empty
  int threads = 0;              // OpenMP threads for DEM and coarse-graining; 0: the default
  bool resume = false;          // continue the DEM stage from its checkpoint
};

/// What the report needs from the stages (filled in as they run).
struct StudyResults {
  struct Stage {
    std::string name, what;
    double wall_seconds = 0;
  };
  std::vector<Stage> stages;
  std::vector<std::string> warnings;  // from every stage, prefixed with the stage's name
  // dem
  std::map<std::string, std::string> dem_summary;  // summary.yaml's scalar entries
  // cg
  int cg_snapshots = 0;
  double cg_mass_error = 0;
  double dem_t_first = 0, dem_t_last = 0;
  double dem_coverage_centre = 0, dem_coverage_left = 0, dem_coverage_right = 0;
  double dem_index_left = 0, dem_index_right = 0;
  double dem_coverage_centre_first = 0, dem_coverage_ends_first = 0;
  std::vector<std::string> cg_figures;
  int flow_snapshots = 0;
  // fit
  double t0 = 0, initial_c = 0;
  int fit_frames = 0;
  std::vector<std::string> fit_names;
  std::vector<double> fit_values, fit_errors, fit_starts;
  std::vector<std::string> fit_units;
  double chi2_per_dof = 0;
  int fit_iterations = 0;
  bool fit_converged = false;
  // predict
  double predict_end = 0;
  double chaff_initial = 0, chaff_final = 0, c_min = 0, c_max = 0;
  double coverage_centre = 0, coverage_left = 0, coverage_right = 0;
  double coverage_centre_first = 0, coverage_ends_first = 0;
};

class StudyRun {
 public:
  StudyRun(StudySettings settings, StudyOptions options);
  void setup();
  void run();
  void output();
  const StudyResults& results() const { return results_; }
  const std::string& output_directory() const { return out_; }

 private:
  void dem();
  void coarse_grain();
  void fit();
  void predict();
  void log(const std::string& line);
  void stage_done(const std::string& name, const std::string& what, double started);
  std::string path(const std::string& relative) const;  // inside the output folder

  StudySettings s_;
  StudyOptions o_;
  std::string out_;
  std::optional<StudyFolder> folder_;
  StudyResults results_;
};

}  // namespace grainscale::studies
