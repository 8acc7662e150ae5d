#pragma once
// Checkpoints: the complete state of a DEM run in one HDF5 file, from which the run continues bit
// for bit as if it had never stopped. Layout (a contract, like the snapshots'): docs/checkpoint_layout.md;
// change it only together with kCheckpointFormatVersion and that document.
//
// Why "complete" is more than positions and velocities: the force on a sphere is a sum over its
// neighbour-list entries in slot order, and floating-point addition is not associative, so the next
// step reproduces the original only with the same slot order, the same neighbour list (entries and
// their order) and the same contact histories. A checkpoint therefore stores the sphere arrays in
// slot order (including the positions at the last neighbour-list build, which decide when the next
// rebuild happens), the list itself, the wall-contact histories, the forces of the last step (the
// first half kick uses them) and, for a scenario run, the pours and the random generator. Wall poses
// are not stored: walls move as a function of time (dem/wall.hpp), so they are recomputed.
//
// Writing is atomic (dem/atomic_file.hpp): a crash or full disk while writing leaves the previous
// checkpoint in place. A state that is not finite is never written, so a blow-up keeps the last good one.
#include <cstdint>
#include <string>
#include <vector>

#include "dem/pour.hpp"
#include "dem/scenario.hpp"
#include "dem/simulation.hpp"

namespace grainscale::dem {

/// Version of the layout written by write_checkpoint; the only one read_checkpoint accepts.
inline constexpr int kCheckpointFormatVersion = 1;
/// Value of the root attribute `format`, so that a checkpoint is not mistaken for a snapshot.
inline constexpr const char* kCheckpointFormat = "grainscale DEM checkpoint";

/// A DEM run's own bookkeeping (dem/dem_run.hpp), kept with the state so that a resumed run also
/// continues its output: the snapshot series, the next snapshot time, the time spent.
struct RunRecord {
  std::vector<std::string> scenario;       // scenario_fingerprint() of the scenario being run
  double next_snapshot = 0;                // s simulated: when the next snapshot is due
  std::vector<double> snapshot_time;       // the snapshots written so far ...
  std::vector<std::string> snapshot_file;  // ... relative to the output folder ...
  std::vector<std::uint64_t> snapshot_particles;  // ... and their sphere counts
  double wall_seconds = 0;                 // wall-clock time run so far
  bool settled = false;                    // the run ended early, settled (scenario time.settle_kinetic_energy)
  bool warned_stability = false;           // the step-stability warning was given
  bool complete = false;                   // written at the end of the run, not part-way
};

/// What read_checkpoint returns; restore_checkpoint moves it into a simulation.
struct Checkpoint {
  std::string path;
  int format_version = 0;
  std::string code_version;                // "<version> <git revision>" of the writer
  std::vector<std::string> material_names, wall_names;
  SimulationState simulation;
  bool has_scenario = false;               // written from a BuiltScenario: pours and random state
  std::vector<Pour::State> pours;
  std::string random;                      // Random::state()
  bool has_run = false;                    // written by a DemRun
  RunRecord run;
};

/// "<version> <git revision>" of this build, as checkpoints record it.
std::string checkpoint_code_version();

/// Write the state of a set-up simulation (after setup() or a step) to `path` atomically. Throws
/// std::runtime_error naming the path and the reason if the file cannot be written (an existing
/// checkpoint at `path` is then untouched) or if the state is not finite (a blow-up in progress must
/// not replace the last good checkpoint), std::logic_error if `sim` was never set up.
void write_checkpoint(const std::string& path, const Simulation& sim);
/// The same for a scenario run: also its pours and random numbers, and the DemRun's record if given.
void write_checkpoint(const std::string& path, const BuiltScenario& run, const RunRecord* record = nullptr);

/// Read a checkpoint. Throws InputError naming the file and the object if the file is missing, not
/// HDF5, not a checkpoint, of another format_version, or lacks or mis-shapes anything.
Checkpoint read_checkpoint(const std::string& path);

/// The few facts read_checkpoint_info gives without reading the state (cheap for any size).
struct CheckpointInfo {
  double time = 0;
  std::uint64_t step = 0;
  std::string code_version;
  bool has_run = false, complete = false;  // RunRecord::complete
};
/// Read just those; the same errors as read_checkpoint for a file that is not a checkpoint.
CheckpointInfo read_checkpoint_info(const std::string& path);

/// Move a checkpoint's state into `sim`, a simulation built like the one that wrote it (same
/// materials and walls, in the same order; its particles are replaced). Throws InputError naming the
/// file if the materials or walls differ or the state is inconsistent; `sim` is then unchanged.
void restore_checkpoint(Checkpoint&& c, Simulation& sim);
/// The same for a scenario run, with its pours and random numbers; `run` must come from build() of
/// the same scenario.
void restore_checkpoint(Checkpoint&& c, BuiltScenario& run);

}  // namespace grainscale::dem
