#pragma once
// A DEM scenario file (YAML; format in docs/scenario.md): materials, walls, particles to insert, the
// contact and time-step settings, the duration and what to write. load_scenario() validates it all,
// build() turns it into a ready Simulation.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dem/insertion.hpp"
#include "dem/pour.hpp"
#include "dem/simulation.hpp"

namespace grainscale::dem {

struct WallSpec {
  std::string name;
  std::string material;
  std::shared_ptr<const WallGeometry> geometry;
  WallPose pose;
  WallMotion motion;  // no profile: the wall stays put
};

struct BatchSpec {
  std::string material;
  ParticleBatch batch;  // material index filled in by build()
  double particle_mass = 0;  // kg per clump: sets the clump density (reported); 0 = material density
  double rate = 0;           // kg/s: poured during the run from `start`; 0 = all placed at t = 0
  double start = 0;          // s
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
  double pour_interval = 0.01;       // s between pour insertions
  double settle_kinetic_energy = 0;  // J: stop early once all pours are done and KE is below; 0 = off
  std::string output_directory;      // relative to the working directory unless absolute
  double snapshot_interval = 0;      // s simulated; 0 = only the final state
  double progress_interval = 5;      // s of wall-clock time between progress lines
  double checkpoint_interval = 600;  // s of wall-clock time between checkpoints (and one at the end)
};

/// Parse and validate; every problem is an InputError naming file, line, key and allowed range.
Scenario load_scenario(const std::string& file);

/// Lines "key: value" that identify everything in a scenario that changes the dynamics: seed,
/// materials and pairs (as loaded), contact and time-step settings, each wall (geometry, pose, its
/// motion sampled at fixed times) and each batch. Not the end time, the settling threshold or the
/// output settings, which a resumed run may change. Numbers are exact (shortest round trip); no
/// line depends on where the files are. `--resume` compares these with the checkpoint's.
std::vector<std::string> scenario_fingerprint(const Scenario& s);

/// A scenario turned into a running system: the simulation, the pours still going, and the random
/// numbers they draw from (seeded by the scenario, so runs repeat exactly).
struct BuiltScenario {
  std::unique_ptr<Simulation> sim;
  std::vector<Pour> pours;
  Random rng{1};
  std::vector<std::string> report;  // one line per batch placed at t = 0 (count, mass, density)

  /// One step, with the pours inserting what is due first; once every pour is done, `steps` steps
  /// in one go (Simulation::run_steps).
  void advance(std::uint64_t steps = 1);
  bool pouring() const;
  /// Lines describing each pour so far (placed count, mass, times the region was full).
  std::vector<std::string> pour_report() const;
};

/// Materials, walls and the particles placed at t = 0; pours are set up to run with advance().
/// With an automatic time step and pours, the step is chosen now for the smallest particle of any
/// batch, so poured particles never need a smaller one. `place_particles` false leaves the t = 0
/// batches out (a run resumed from a checkpoint gets its particles from there).
BuiltScenario build(const Scenario& s, bool place_particles = true);

}  // namespace grainscale::dem
