#pragma once
// Constant velocity and constant angular velocity: d(t) = v t, R(t) = rotation by |omega| t about
// omega. The angle-of-repose rig's pipe lifted at a set speed, a turntable, a conveyor.
#include <cmath>
#include <sstream>

#include "dem/motion_profile.hpp"

namespace grainscale::dem {

class SteadyMotion final : public MotionProfile {
 public:
  SteadyMotion(const Vec3& velocity, const Vec3& angular_velocity) : v_(velocity), w_(angular_velocity) {}

  RigidMotionState at(double t) const override {
    RigidMotionState s;
    const double rate = norm(w_);
    if (rate > 0) s.rotation = axis_angle((1.0 / rate) * w_, rate * t);
    s.angular_velocity = w_;
    s.displacement = t * v_;
    s.velocity = v_;
    return s;
  }
  double period() const override { return 0; }
  std::string describe() const override {
    std::ostringstream o;
    o << "steady: velocity (" << v_.x << ", " << v_.y << ", " << v_.z << ") m/s, angular velocity (" << w_.x << ", "
      << w_.y << ", " << w_.z << ") rad/s";
    return o.str();
  }

 private:
  Vec3 v_, w_;
};

}  // namespace grainscale::dem
