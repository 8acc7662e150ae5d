#pragma once
// The scenario's `motion:` block of a wall, turned into a MotionProfile. Adding a profile: one more
// `type` here and its class in dem/motion/.
//
//   motion: {type: platform, amplitude_deg: 24, frequency: 0.1, pause: 4, axis: [0, 1, 0], start: level}
//   motion: {type: sinusoids, roll: {amplitude_deg: 20, period: 12, phase_deg: 0},
//            heave: {amplitude: 1.5, period: 8}}           # any of roll pitch yaw surge sway heave
//   motion: {type: steady, velocity: [0, 0, 0.01], angular_velocity: [0, 0, 0]}   # m/s, rad/s
//   motion: {type: record, file: roll_record.csv}        # t_s,roll_deg,pitch_deg,yaw_deg,surge_m,sway_m,heave_m
// Every type also takes `start_time` (s, default 0): at rest until then (dem/motion/delayed_motion.hpp).
// Beside `motion`, the wall takes `pivot: [x, y, z]` (m, world frame at rest; default the origin).
#include <memory>

#include "dem/motion_profile.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::dem {

/// Reads and checks the mapping (unknown keys and out-of-range values throw InputError naming the
/// file, line and key). `end_time`: the run's end, which a recorded motion must cover.
std::shared_ptr<const MotionProfile> motion_from_yaml(YamlMap m, double end_time);

}  // namespace grainscale::dem
