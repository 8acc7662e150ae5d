#pragma once
// One candidate physical trial of the `trial_planning` study (docs/studies.md): a container length,
// fill depth, tilt amplitude, cycle period and a named motion, applied to the study's base
// `grainscale hold` settings (docs/hold_prediction.md) to give the hold-scale prediction of that
// trial. The named motions are the DEM's own motion blocks (dem/motion/motion_from_yaml.hpp: the
// report's platform, sinusoids for a truck body or a chaser bin), each with where its rotation axis
// sits relative to the container; the sweep's amplitude and period rescale them:
//  - platform: amplitude_deg = A; the cycle T = 1/f + 2 pause (platform_tilt.hpp) is set to the
//    period P by f = 1/(P − 2 pause), the pauses kept (so P must exceed 2 pause);
//  - sinusoids: the largest rotational amplitude becomes A and the others keep their ratio to it;
//    every component's period is multiplied by P / (the motion's period), translations unchanged;
//  - record and steady motions cannot be rescaled (an InputError if the sweep asks).
// Cell size, window and integrator step follow the base file (see hold_settings_for).
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "studies/hold_settings.hpp"

namespace grainscale::studies {

/// A motion the sweep can name. "base" is the base hold file's own motion.
struct TrialMotion {
  std::string name;
  YAML::Node block;                   // the DEM motion mapping
  std::string direction = "longitudinal";
  double pivot_x = 0, pivot_z = 0;    // [m]; x from the x = 0 wall, or from the centre if pivot_from_centre
  bool pivot_from_centre = false;
  std::string file, key;              // where the block was read (for messages)
};

/// One design of the sweep, every value resolved (the motion's own amplitude and period where the
/// sweep does not set them).
struct TrialDesign {
  int index = 0;
  std::string motion;
  double length = 0, fill_height = 0;  // [m]
  double amplitude_deg = 0, period = 0;
  bool amplitude_swept = false, period_swept = false;
  std::string label() const;  // "platform L=0.8 m fill=27 mm A=24° T=18 s"
};

/// The motion block with the tilt amplitude and period set (see the header comment); `swept_*`
/// false leaves that part alone. `where` names the sweep entry for messages.
YAML::Node rescaled_motion(const TrialMotion& m, bool set_amplitude, double amplitude_deg, bool set_period,
                           double period, const std::string& where);

/// The amplitude (largest tilt over a cycle, degrees) and period of a motion block as run.
void motion_amplitude_period(const TrialMotion& m, const YAML::Node& block, double& amplitude_deg, double& period);

/// The hold settings of one design: the base with the design's container, fill (the chaff window
/// follows the fill when the base models the whole bed), motion, pivot and direction; the cell size
/// and the chaff step's fraction of the cycle kept; the run `duration` seconds long with `resolve`
/// cycles resolved (0: all) and the last `average_cycles` of them averaged; one output at the end;
/// end zones of min(`end_length`, L/2). The chaff terms are deep copies (safe to run in parallel).
HoldSettings hold_settings_for(const HoldSettings& base, const TrialMotion& motion, const TrialDesign& d,
                               double duration, long resolve, long average_cycles, double end_length);

}  // namespace grainscale::studies
