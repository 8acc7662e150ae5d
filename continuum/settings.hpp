#pragma once
// The YAML input of a continuum run (docs/continuum.md, "Input"), read with checked access: every
// error is an InputError naming file, line, key and allowed range; unknown keys are rejected.
#include <yaml-cpp/yaml.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "continuum/integrator.hpp"
#include "continuum/model.hpp"
#include "continuum/observation.hpp"

namespace grainscale::continuum {

struct FlowSettings {
  std::string type = "cellular";  // cellular | uniform_shear | file | sloshing
  double amplitude = 0;           // cellular: ψ amplitude [m²/s]
  double background_shear = 0;    // cellular: γ̇ added everywhere [1/s]
  double shear_rate = 0;          // uniform_shear [1/s]
  std::string file;               // file: HDF5 fields (gridded_flow.hpp), resolved beside the YAML
  int frame = -1;                 // file from `grainscale cg`: frame to use (negative: from the end)
  // file from `grainscale cg`: the rate the terms' mobility follows (gridded_flow.hpp): 0, the shear
  // rate of the mean flow; > 0, sqrt(T) / d from the granular temperature T with d this diameter [m]
  double temperature_diameter = 0;
  bool volume_flux = false;  // flux: volume (GriddedFlow::load)
  // file with `period`: phase-resolved fields (phase_resolved_flow.hpp), phase 0 at t0
  bool phase_resolved = false;
  double t0 = 0;                  // [s]
  bool moving_surface = true;     // surface: moving | fixed
  // sloshing (analytic_flows.hpp SloshingFlow; depth = grid.depth): moving free surface
  double period = 0;              // [s] (also the motion period of phase-resolved fields)
  int mode = 1;
  double exponent = 2;
  double cell = 0;                // convection-cell amplitude [m²/s]
};

struct InitialSettings {
  std::string type = "uniform";  // uniform | layers | file
  double value = 0;              // uniform
  double below = 0, above = 0;   // layers: c below and above σ = split
  double split = 0.5;
  std::string file;              // file: a cg fields.h5 (initial_from_fields.hpp)
  int frame = 0;                 //   its frame (negative counts from the end)
  double min_solid_fraction = 0.3;  // its cells below this solid fraction are not bed
};

struct ContinuumSettings {
  std::string source_file;
  Closure closure = Closure::resolved;  // model.type: resolved | depth_averaged
  double cycle_period = 0;              // model.cycle_average.period [s] (depth_averaged only)
  int cycle_phases = 0;                 // model.cycle_average.phases; 0: no cycle averaging
  double length = 0;               // [m]
  int nx = 0, nz = 0;
  std::vector<double> surface;     // h at the nx + 1 column faces [m] (from `depth` or `surface`)
  FlowSettings flow;
  std::vector<std::pair<std::string, YAML::Node>> terms;  // built by build_model() via the registry
  InitialSettings initial;
  double t_end = 0;
  int outputs = 1;                 // equally spaced output times in (0, t_end]
  std::vector<double> stops;       // forcing jumps: the integrator stops and restarts there
  IntegratorSettings integrator;
  double kappa = 100, delta = 4e-3;  // observation (O1)
  std::string output_folder;
  double slice_width = 0.05;       // [m] width of the chaff-per-slice bins
};

/// Read and validate (also builds the model once, so term errors surface here).
ContinuumSettings load_continuum_settings(const std::string& yaml_file);

std::shared_ptr<const Flow> build_flow(const ContinuumSettings& s, const Grid& grid);
Model build_model(const ContinuumSettings& s);
std::vector<double> initial_field(const ContinuumSettings& s, const Grid& grid);
std::vector<double> output_times(const ContinuumSettings& s);

}  // namespace grainscale::continuum
