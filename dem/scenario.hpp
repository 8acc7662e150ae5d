#pragma once
// A DEM scenario file (YAML; format in docs/scenario.md): materials, walls, particles to insert, the
// contact and time-step settings, the duration and what to write. load_scenario() validates it all,
// build() turns it into a ready Simulation.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dem/insertion.hpp"
#include "dem/simulation.hpp"

namespace grainscale::dem {

struct WallSpec {
  std::string name;
  std::string material;
  std::shared_ptr<const WallGeometry> geometry;
  WallPose pose;
};

struct BatchSpec {
  std::string material;
  ParticleBatch batch;  // material index filled in by build()
  double particle_mass = 0;  // kg per clump: sets the clump density (reported); 0 = material density
};

struct Scenario {
  std::string file;  // the YAML it came from
  std::string name;
  std::uint64_t seed = 1;
  std::string materials_file;
  SimulationSettings settings;
  std::vector<WallSpec> walls;
  std::vector<BatchSpec> particles;
  double end_time = 0;               // s simulated
  std::string output_directory;      // relative to the working directory unless absolute
  double snapshot_interval = 0;      // s simulated; 0 = only the final state
  double progress_interval = 5;      // s of wall-clock time between progress lines
};

/// Parse and validate; every problem is an InputError naming file, line, key and allowed range.
Scenario load_scenario(const std::string& file);

/// Materials, walls and inserted particles; call setup() (or step()) next. If `report` is given, one
/// line per particle batch is appended: how many were placed, their mass, and the density used.
std::unique_ptr<Simulation> build(const Scenario& s, std::vector<std::string>* report = nullptr);

}  // namespace grainscale::dem
