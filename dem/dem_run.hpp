#pragma once
// `grainscale dem SCENARIO.yaml [--resume]`: the run as the algorithm reads -
//   setup();   load and validate the scenario, insert particles, choose the time step
//              (or, resuming, restore the state from the output folder's checkpoint)
//   run();     step to the end time, writing snapshots, progress and checkpoints
//   output();  final snapshot, XDMF series, summary
// Output folder: inputs/ (copies of the scenario and materials), snapshots/*.h5, snapshots.xmf,
// summary.yaml, log.txt, checkpoint.h5.
//
// Checkpoints (dem/checkpoint.hpp) are written every `output.checkpoint_interval` seconds of wall
// clock and at the end, atomically, and never from a state that has blown up. A run resumed from one
// ends bitwise identical to a run that was never interrupted: the same final snapshot, byte for byte.
#include <chrono>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dem/checkpoint.hpp"
#include "dem/scenario.hpp"
#include "dem/snapshot.hpp"

namespace grainscale::dem {

class DemRun {
 public:
  /// `output_override` replaces the scenario's output directory if not empty. With `resume`, setup()
  /// continues the run whose checkpoint is in the output directory instead of starting afresh.
  DemRun(std::string scenario_file, std::string output_override = "", bool resume = false);
  void setup();
  void run();
  void output();

  /// Called after every checkpoint is written, with its path (tests stop a run there, as a kill would).
  void on_checkpoint(std::function<void(const std::string&)> f) { on_checkpoint_ = std::move(f); }

  const Simulation& simulation() const { return *run_.sim; }
  const std::string& output_directory() const { return out_dir_; }
  std::string checkpoint_path() const;

 private:
  /// Steps the run loop may take in one go before its next check (at least 1).
  std::uint64_t steps_to_next_check(const Simulation& sim, std::uint64_t steps_left) const;
  /// Steps left to the end time: with a fixed step, to the step count end / dt; with the step
  /// control (dem/step_control.hpp), at the present step, to within half a step of the end.
  std::uint64_t steps_left(const Simulation& sim) const;
  void log(const std::string& line);
  void write_snapshot_now();
  void write_checkpoint_now();
  void write_final_output();
  void resume_from(Checkpoint&& c);
  double wall_seconds() const;

  std::string scenario_file_, out_dir_;
  bool resume_ = false;
  Scenario scenario_;
  std::vector<std::string> fingerprint_;  // scenario_fingerprint(scenario_) at setup
  BuiltScenario run_;
  std::ofstream log_;
  std::vector<XdmfFrame> snapshots_;
  double next_snapshot_ = 0;           // s simulated
  double wall_seconds_before_ = 0;     // spent by the run before it was resumed
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  bool warned_stability_ = false;
  bool settled_ = false;               // ended early: every pour done and the kinetic energy low
  double checkpoint_time_ = -1;        // s simulated of the last checkpoint written or resumed from
  std::function<void(const std::string&)> on_checkpoint_;
};

}  // namespace grainscale::dem
