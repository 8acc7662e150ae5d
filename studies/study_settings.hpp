#pragma once
// A study file (`grainscale study FILE.yaml`): which stage files to chain, and what the study adds
// to them - where each stage reads its predecessor's output, what the fit uses, how far the
// prediction goes. The stage files themselves are ordinary DEM scenario, coarse-graining and
// continuum settings files (docs/scenario.md, docs/coarsegrain_layout.md, docs/continuum.md), so
// every stage can also be run alone. Format and keys: docs/studies.md.
//
// Read with dem/yaml_map.hpp: unknown keys, wrong types and out-of-range values are InputErrors
// naming the file, the line and the key. Relative paths are relative to the study file.
#include <string>
#include <vector>

namespace grainscale::studies {

struct StudySettings {
  std::string source_file;  // the study file, as given
  std::string name, title, description;

  // dem
  std::string scenario;  // resolved path of the DEM scenario

  // cg
  std::string cg_settings;  // resolved path of the coarse-graining settings
  double flow_from = 0;     // s: the continuum flow is the window average of snapshots at t >= flow_from
  double flow_to = 1e300;   // s: ... and t <= flow_to

  // fit
  std::string model;                    // resolved path of the continuum settings (grid, terms, ...)
  std::vector<std::string> fit_parameters;
  bool fit_fields = true, fit_coverage = true;
  double field_sigma = 0.02, coverage_sigma = 0.05;
  double data_from = 0;  // s: the model starts from the DEM's state at the first frame at or after this
  int data_every = 1;    // use every n-th coarse-grained frame after data_from
  double min_solid_fraction = 0.3;  // cells with a lower solid fraction are not bed (not fitted)
  int max_iterations = 30;

  // predict
  double predict_end = 1800;  // s of motion after data_from
  int predict_outputs = 12;

  // comparison with the report's measurement (top-view coverage after 30 min)
  double end_length = 0.1;    // m: end zone and centre zone length for the coverage comparison

  std::string output_directory;  // resolved
};

/// Throws InputError.
StudySettings load_study_settings(const std::string& yaml_file);

}  // namespace grainscale::studies
