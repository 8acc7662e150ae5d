#pragma once
// Settings of a coarse-graining run, read from YAML with every key checked (dem/yaml_map.hpp: unknown
// keys are rejected, numbers are range-checked, errors name file, line and key). The keys are listed
// with their ranges and defaults in docs/coarsegrain_layout.md ("Settings").
#include <array>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "coarsegrain/fields.hpp"
#include "coarsegrain/kernel.hpp"
#include "coarsegrain/top_view.hpp"
#include "dem/vec3.hpp"

namespace grainscale::cg {

enum class Averaging { snapshot, window, phase, cycles };
const char* name(Averaging a);

struct SnapshotEntry {
  std::string path;  // resolved (absolute, or relative to the working directory)
  double phase;      // in cycles; NaN: from the time and averaging.period
};

struct CgSettings {
  std::string source;  // the settings file, for messages
  std::vector<SnapshotEntry> snapshots;
  std::string container_wall;  // empty: the world frame
  dem::Vec3 lo, hi;            // grid box in the container frame, m
  int dimension = 2;
  std::array<int, 3> cells{1, 1, 1};
  KernelType kernel = KernelType::gaussian;
  Boundary boundary = Boundary::reflect;
  double width_diameters = 1;
  double true_diameter = 0;        // m; 0: mean sphere diameter of diameter_species / scale_factor
  std::string diameter_species;    // empty: all non-chaff species (all species if every one is chaff)
  std::vector<std::string> chaff;  // species counted as chaff
  std::map<std::string, double> density;
  Averaging averaging = Averaging::snapshot;
  int phase_bins = 8;
  double period = 0, t0 = 0;  // s; phase = (t - t0) / period where a snapshot has no phase;
                              // cycles: the k-th frame averages [t0 + k period, t0 + (k + 1) period)
  double from = -std::numeric_limits<double>::infinity();  // s: snapshots outside [from, to] are skipped
  double to = std::numeric_limits<double>::infinity();
  FieldOptions surface;
  double slice_width = 0.05, end_length = 0.1;
  TopViewSettings top_view;
  std::string output_dir;
};

/// Read and check a settings file. Relative paths (snapshots, snapshot_dir, output) are taken
/// relative to the settings file's directory. Throws InputError.
CgSettings load_cg_settings(const std::string& yaml_file);

}  // namespace grainscale::cg
