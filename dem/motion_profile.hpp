#pragma once
// Prescribed rigid motion of a wall (a container, a platform, a ship's hold) as a function of time.
// A profile gives a rotation R(t) about the wall's pivot and a translation d(t) of it:
//
//   x(t) = pivot + d(t) + R(t) (x0 - pivot)        x0: the point's position at rest (R = 1, d = 0)
//
// together with their first and second time derivatives, which must be consistent with R and d
// (tests/dem/test_motion.cpp checks them by finite differences): the wall's surface velocity enters
// the contact forces, and its acceleration is what a container frame's fictitious forces would need.
// `phase` is the position in the motion cycle in [0, 1) (0 for a non-periodic motion); snapshots
// record it so that fields can be phase-averaged.
//
// Adding a profile: a class implementing MotionProfile in dem/motion/, and one line in
// dem/motion/motion_from_yaml.cpp.
#include <string>

#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

struct RigidMotionState {
  Quat rotation;               // R(t), about the pivot
  Vec3 angular_velocity;       // omega(t), world frame, rad/s
  Vec3 angular_acceleration;   // d omega / dt, rad/s^2
  Vec3 displacement;           // d(t), m
  Vec3 velocity;               // d'(t), m/s
  Vec3 acceleration;           // d''(t), m/s^2
  double phase = 0;            // in [0, 1)
};

class MotionProfile {
 public:
  virtual ~MotionProfile() = default;
  virtual RigidMotionState at(double t) const = 0;
  /// Period of the motion cycle in s (0 if not periodic).
  virtual double period() const = 0;
  virtual std::string describe() const = 0;
};

}  // namespace grainscale::dem
