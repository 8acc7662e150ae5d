#pragma once
// What `grainscale loop` needs from the experiment's DEM scenario (docs/scenario.md): the container's
// motion cycle and where its rotation axis lies in the container frame. These set the non-fitted
// parameters of candidate effects (lever_arm: ⟨ω²⟩, ⟨α²⟩ and the axis; pause_creep: the pause fraction)
// and the period for the harmonic split of the residual.
#include <string>

#include "dem/motion_profile.hpp"

namespace grainscale::studies {

struct MotionFacts {
  std::string container;       // the wall whose frame the fields are in
  double period = 0;           // s, 0: not periodic
  double omega2_mean = 0;      // cycle mean of |ω|² [1/s²]
  double alpha2_mean = 0;      // cycle mean of |α|² [1/s⁴] (the Euler term's strength)
  double pause_fraction = 0;   // fraction of the cycle with |ω| < 1e-6 rad/s
  double axis_x = 0, axis_z = 0;  // the pivot in the container's rest frame [m]
  double peak_angle_deg = 0;   // largest tilt over the cycle
};

/// Sample the container wall's motion over one cycle (after its start). `container` names the wall;
/// empty: the first moving wall. InputError (file, key) if the scenario has no moving wall or no
/// wall of that name, or the motion is not periodic.
MotionFacts motion_facts(const std::string& scenario_file, const std::string& container);

/// The cycle facts of a periodic motion alone (period, ⟨ω²⟩, ⟨α²⟩, pause fraction, peak angle), sampled
/// over one cycle well after any start-up transition; container and axis are left empty.
MotionFacts cycle_facts(const dem::MotionProfile& motion);

}  // namespace grainscale::studies
