#pragma once
// One virtual angle-of-repose test: load the generated rig scenario (studies/aor_rig.hpp), pour and
// settle the fill, lift the pipe, wait until the pile is at rest (or a time limit), and measure the
// angle from the particle positions (studies/aor_angle.hpp). Unlike `grainscale dem`, which runs to
// the scenario's end time, this loop knows the rig: it records the fill at the lift, computes when
// the pipe has cleared the grain, and stops as soon as the grain on the tray is at rest.
#include <functional>
#include <string>
#include <vector>

#include "studies/aor_angle.hpp"
#include "studies/aor_rig.hpp"

namespace grainscale::studies {

struct AorRunResult {
  AngleMeasurement angle;
  bool at_rest = false;          // the pile came to rest before clear_time + max_settle
  double lift_start = 0;         // s simulated
  double clear_time = 0;         // s: the pipe's bottom is above the fill's top
  double end_time = 0;           // s: when the loop stopped
  double speed_p95 = 0;          // m/s: 95th-percentile speed of the grain on the tray at the end
  double fill_top = 0;           // m: top of the highest grain in the pipe at the lift
  double fill_speed_p95 = 0;     // m/s: 95th-percentile speed of the fill at the lift
  bool pour_done = false;        // the pour had finished when the lift began
  std::size_t spheres = 0, bodies = 0;
  std::size_t bodies_on_tray = 0;  // centre within the tray's radius and above the floor
  double time_step = 0;          // s
  double wall_seconds = 0;
  double max_overlap_ratio = 0;      // at the end
  double max_stability_margin = 0;   // worst over the run (dem/step_stability.hpp; > 1 unstable)
  std::vector<std::string> warnings;  // narrow passages, unfinished pour, fill too high, not at rest
};

/// Run the scenario `scenario_file` (written by aor_scenario_yaml for `c`); write the final snapshot
/// to `snapshot_file` if not empty. `log` receives progress and warning lines.
AorRunResult run_aor(const std::string& scenario_file, const AorCase& c, const std::string& snapshot_file,
                     const std::function<void(const std::string&)>& log);

}  // namespace grainscale::studies
