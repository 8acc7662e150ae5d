#pragma once
// Plain sinusoids in any of the six degrees of freedom (roll, pitch, yaw about x, y, z; surge,
// sway, heave along x, y, z): q_k(t) = a_k sin(2 pi f_k t + phi_k). Rotations compose as in
// dem/motion/euler_angles.hpp. Periodic with the longest period when all frequencies share one
// (phase is reported for that period; 0 if the frequencies differ).
#include <array>
#include <string>

#include "dem/motion_profile.hpp"

namespace grainscale::dem {

class SinusoidalMotion final : public MotionProfile {
 public:
  struct Dof {
    double amplitude = 0;  // rad for roll, pitch, yaw; m for surge, sway, heave
    double frequency = 0;  // Hz
    double phase = 0;      // rad
  };
  /// roll, pitch, yaw, surge, sway, heave
  explicit SinusoidalMotion(const std::array<Dof, 6>& dofs);

  RigidMotionState at(double t) const override;
  double period() const override { return period_; }
  std::string describe() const override;

 private:
  std::array<Dof, 6> d_;
  double period_ = 0;
};

}  // namespace grainscale::dem
