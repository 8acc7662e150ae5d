#pragma once
// The study file of a `kind: hold` study (`grainscale study studies/hold_prediction.yaml`,
// docs/studies.md "hold"): which hold settings files (docs/hold_prediction.md) to run, each into its
// own subfolder, optionally shortened, and an optional comparison of the flow closure with the
// coarse-grained DEM flow of a platform box. Every scenario file is loaded (and so checked) when the
// study file is read, so a typo in the last scenario does not cost the first one's run.
//
//   kind: hold
//   name: hold_prediction                 a word (no '/'): the report's heading if no title
//   title: "..."  description: >...      optional
//   scenarios:                            one or more
//     - {file: hold_handysize_partial.yaml}               relative to the study file
//     - {file: hold_truck.yaml, end: 600}                 end: shorten to this many s (<= the file's end)
//     - {file: hold_platform_box.yaml, compare_with_report: true}   the report's 800 mm box: compare its
//                                                         end/centre surface chaff with the report's photographs
//   validate:                             optional: the closure against coarse-grained DEM flow
//     cg_fields: ../runs/platform_quick/cg/fields.h5   a `grainscale cg` fields.h5 (snapshot frames)
//     dem_scenario: platform_quick/scenario.yaml       that DEM run's scenario (box, motion, pivot)
//     container: box                                   its moving wall (default: the first moving one)
//     material_from: platform_box                      the listed scenario whose bed friction is used
//     measure_depth: 0.02                              optional: the surface speed's depth [m] (default:
//                                                      the closure's flowing layer)
//     fit: {train_until: 16}                           optional: calibrate that friction on the frames
//                                                      t <= 16 s, judge it on the later ones
//                                                      (closure_friction_fit.hpp; `parameters: [...]`
//                                                      default internal, basal, flowing_layer_diameters)
//   output: {directory: ../runs/hold_prediction}
#include <optional>
#include <string>
#include <vector>

#include "studies/closure_friction_fit.hpp"
#include "studies/hold_settings.hpp"

namespace grainscale::studies {

struct HoldStudyScenario {
  std::string file;                  // resolved path of the hold settings file
  HoldSettings settings;             // loaded, shortened if asked, output folder set by the runner
  double file_end = 0;               // the file's own time.end [s]
  bool shortened = false;
  bool compare_with_report = false;  // the report's 800 mm box: compare with its top-view coverage
};

/// Closure vs coarse-grained DEM (closure_dem_comparison.hpp).
struct HoldStudyValidation {
  std::string cg_fields;     // a `grainscale cg` fields.h5 (snapshot frames) of a platform box DEM run
  std::string dem_scenario;  // that run's DEM scenario (container, motion, pivot)
  std::string container;     // its wall whose frame the fields are in (empty: the first moving wall)
  std::string material_from; // name of a listed scenario whose bed friction the closure uses
  double measure_depth = NAN;  // [m]; NaN: the closure's flowing layer
  std::optional<ClosureFitSettings> fit;
};

struct HoldStudySettings {
  std::string source_file, name, title, description;
  std::vector<HoldStudyScenario> scenarios;
  std::optional<HoldStudyValidation> validate;
  std::string output_directory;  // resolved
};

/// Throws InputError naming file, line and key (unknown keys, no scenarios, a missing or bad
/// scenario file, two scenarios with the same name, `end` out of range).
HoldStudySettings load_hold_study_settings(const std::string& yaml_file);

/// Shortens a loaded hold to `end` seconds (0 < end <= s.t_end): the resolved cycles are capped at
/// the new total ("all" stays all), so the averaged model still has its averaging cycles.
void shorten_hold(HoldSettings& s, double end);

}  // namespace grainscale::studies
