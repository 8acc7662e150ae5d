#include "dem/motion/sinusoidal_motion.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "dem/motion/euler_angles.hpp"

namespace grainscale::dem {

SinusoidalMotion::SinusoidalMotion(const std::array<Dof, 6>& dofs) : d_(dofs) {
  double f = 0;
  bool common = true;
  for (const Dof& d : d_) {
    if (d.amplitude == 0 || d.frequency == 0) continue;
    if (f == 0) f = d.frequency;
    else if (d.frequency != f) common = false;
  }
  period_ = (common && f > 0) ? 1 / f : 0;
}

RigidMotionState SinusoidalMotion::at(double t) const {
  double q[6], dq[6], ddq[6];
  for (int k = 0; k < 6; ++k) {
    const double w = 2 * std::numbers::pi * d_[k].frequency;
    const double arg = w * t + d_[k].phase;
    q[k] = d_[k].amplitude * std::sin(arg);
    dq[k] = d_[k].amplitude * w * std::cos(arg);
    ddq[k] = -d_[k].amplitude * w * w * std::sin(arg);
  }
  RigidMotionState s;
  set_rotation({{q[0], q[1], q[2]}, {dq[0], dq[1], dq[2]}, {ddq[0], ddq[1], ddq[2]}}, s);
  s.displacement = {q[3], q[4], q[5]};
  s.velocity = {dq[3], dq[4], dq[5]};
  s.acceleration = {ddq[3], ddq[4], ddq[5]};
  s.phase = period_ > 0 ? std::fmod(std::fmod(t, period_) + period_, period_) / period_ : 0;
  return s;
}

std::string SinusoidalMotion::describe() const {
  static const char* names[6] = {"roll", "pitch", "yaw", "surge", "sway", "heave"};
  std::ostringstream o;
  o << "sinusoids:";
  for (int k = 0; k < 6; ++k) {
    if (d_[k].amplitude == 0) continue;
    o << " " << names[k] << " " << (k < 3 ? d_[k].amplitude * 180 / std::numbers::pi : d_[k].amplitude)
      << (k < 3 ? " deg" : " m") << " at " << d_[k].frequency << " Hz;";
  }
  return o.str();
}

}  // namespace grainscale::dem
