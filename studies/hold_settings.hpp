#pragma once
// The YAML of a hold-scale prediction (`grainscale hold SETTINGS.yaml`, docs/hold_prediction.md):
// a container section (a ship's hold, a truck body, a chaser bin, the report's box), its fill, the
// motion (the DEM's own motion profiles: platform, sinusoids, record), the bed's friction, the chaff
// model on the top window of the bed, and how days of motion are covered (resolved cycles, then the
// cycle-averaged slow-time model). Every error is an InputError naming file, key and range.
#include <yaml-cpp/yaml.h>

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "continuum/closure/shallow_granular_flow.hpp"
#include "continuum/integrator.hpp"
#include "dem/motion_profile.hpp"

namespace grainscale::studies {

struct HoldSettings {
  std::string source_file, name;
  // Container section and fill.
  double length = 0, depth = 0, fill_height = 0;  // [m]
  bool decked = false;                            // a deck (ceiling) at `depth` (ship holds) vs open top
  double width = std::numeric_limits<double>::infinity();  // between the side walls [m]; ∞: none stated
  int nx = 0;
  // Placement and motion (container_gravity.hpp).
  std::string direction = "longitudinal";  // section along the motion's x (pitch) or y (roll) axis
  double pivot_x = 0, pivot_z = 0;         // motion pivot in the section frame (x along floor from the
                                           // x = 0 wall, z above the floor) [m]
  std::shared_ptr<const dem::MotionProfile> motion;
  continuum::closure::BedFriction friction;
  // Chaff model.
  double window = 0;  // depth of the modelled top layer [m] (≤ fill height)
  int nz = 0;
  double chaff_initial = 0;  // uniform chaff volume fraction at t = 0
  std::vector<std::pair<std::string, YAML::Node>> terms;
  continuum::IntegratorSettings integrator{"ssp_rk3"};  // max_dt defaults to chunk / 100
  // The cycle-averaged slow-time model: steady and linear, its stiffness set by the fitted drift and
  // dispersion of the most mobile face, not by accuracy; BDF (cvode) steps over it (hold_run.hpp).
  continuum::IntegratorSettings averaged_integrator{"cvode"};
  // Time.
  double t_end = 0;
  int outputs = 0;
  double chunk = 0;          // resolved chunk length: the motion period, or `chunk` for a record [s]
  long resolved_chunks = 0;  // chunks resolved before the averaged model takes over (≥ total: all)
  long average_chunks = 0;   // the last this many resolved chunks form the cycle average
  // Output.
  std::string output_folder;
  double top_layer = 0.1, end_zone = 1.0, spear_depth = 1.6, dirty_factor = 2.0;
};

HoldSettings load_hold_settings(const std::string& file);

}  // namespace grainscale::studies
