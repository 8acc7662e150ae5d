#pragma once
// `grainscale dem SCENARIO.yaml`: the run as the algorithm reads -
//   setup();   load and validate the scenario, insert particles, choose the time step
//   run();     step to the end time, writing snapshots and progress
//   output();  final snapshot, XDMF series, summary
// Output folder: inputs/ (copies of the scenario and materials), snapshots/*.h5, snapshots.xmf,
// summary.yaml, log.txt.
#include <fstream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dem/scenario.hpp"
#include "dem/snapshot.hpp"

namespace grainscale::dem {

class DemRun {
 public:
  /// `output_override` replaces the scenario's output directory if not empty.
  DemRun(std::string scenario_file, std::string output_override = "");
  void setup();
  void run();
  void output();

  const Simulation& simulation() const { return *run_.sim; }
  const std::string& output_directory() const { return out_dir_; }

 private:
  void log(const std::string& line);
  void write_snapshot_now();

  std::string scenario_file_, out_dir_;
  Scenario scenario_;
  BuiltScenario run_;
  std::ofstream log_;
  std::vector<XdmfFrame> snapshots_;
  double wall_seconds_ = 0;
  bool warned_stability_ = false;
};

}  // namespace grainscale::dem
