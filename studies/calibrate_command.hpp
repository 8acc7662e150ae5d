#pragma once
// `grainscale calibrate STUDY.yaml [--out DIR] [--threads N] [--case NAME[,NAME]]`: calibrate sliding and/or rolling
// friction against a measured angle of repose with the report's rig (docs/aor_calibration.md).
//
// For each case of the study: a bracketed search (studies/aor_search.hpp) over the case's parameters
// (searched together along the line from their low to their high values), one virtual AOR test per
// point and seed (studies/aor_run.hpp), until the mean angle over the seeds is within the tolerance
// of the target or the budget of runs is spent. Output folder:
//
//   report.md                   what was run, found and how well; warnings; cost
//   runs.csv                    one row per run (case, point, seed, parameter values, angles, cost)
//   <case>_materials.yaml       the materials file with the calibrated values (run scale)
//   <case>_sensitivity.png      angle against each searched parameter, target and tolerance band
//   <case>/run_NN_seed_S/       scenario.yaml (repeats the run with `grainscale dem`), materials.yaml,
//                               log.txt, final.h5 (the pile; ParaView via grainscale's XDMF tools)
//   inputs/                     copies of the study and materials files
#include <string>
#include <vector>

namespace grainscale::studies {

struct CalibrateOptions {
  std::string study_file;
  std::string output_override;  // replaces the study's output directory when not empty
  std::vector<std::string> cases;  // run only these cases (empty: all); unknown names: InputError
};

/// Runs the study; returns 0 when every case converged, 1 when some did not (the report says why).
/// Input problems throw grainscale::InputError.
int run_calibrate(const CalibrateOptions& options);

/// The subcommand: `positional` must be the one study file; `threads` a thread count or empty;
/// `cases` the values of every --case option, each a name or a comma-separated list of names.
int calibrate_main(const std::vector<std::string>& positional, const std::string& out, const std::string& threads,
                   const std::vector<std::string>& cases = {});

}  // namespace grainscale::studies
