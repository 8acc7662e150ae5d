#include "dem/motion/platform_tilt.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace grainscale::dem {

PlatformTilt::PlatformTilt(const Params& p) : p_(p) {
  p_.axis = (1.0 / norm(p.axis)) * p.axis;
  ramp_ = p.start_level ? 0.5 / p.frequency : 0.0;
}

void PlatformTilt::angle(double t, double& theta, double& rate, double& accel) const {
  const double h = 0.5 / p_.frequency;  // duration of one transition
  const double T = period();
  const double A = p_.amplitude, k = std::numbers::pi / h;
  theta = rate = accel = 0;
  if (t < ramp_) {  // the initial rise from level
    theta = 0.5 * A * (1 - std::cos(k * t)), rate = 0.5 * A * k * std::sin(k * t), accel = 0.5 * A * k * k * std::cos(k * t);
    return;
  }
  double s = std::fmod(t - ramp_, T);
  if (s < 0) s += T;
  if (s < p_.pause) {
    theta = A;
  } else if (s < p_.pause + h) {
    const double u = s - p_.pause;
    theta = A * std::cos(k * u), rate = -A * k * std::sin(k * u), accel = -A * k * k * std::cos(k * u);
  } else if (s < 2 * p_.pause + h) {
    theta = -A;
  } else {
    const double u = s - 2 * p_.pause - h;
    theta = -A * std::cos(k * u), rate = A * k * std::sin(k * u), accel = A * k * k * std::cos(k * u);
  }
}

RigidMotionState PlatformTilt::at(double t) const {
  double theta, rate, accel;
  angle(t, theta, rate, accel);
  RigidMotionState s;
  s.rotation = axis_angle(p_.axis, theta);
  s.angular_velocity = rate * p_.axis;
  s.angular_acceleration = accel * p_.axis;  // fixed axis: no gyroscopic term
  const double T = period();
  s.phase = t < ramp_ ? 0.0 : std::fmod(t - ramp_, T) / T;
  return s;
}

std::string PlatformTilt::describe() const {
  std::ostringstream o;
  o << "platform tilt +/-" << p_.amplitude * 180 / std::numbers::pi << " deg about (" << p_.axis.x << ", " << p_.axis.y
    << ", " << p_.axis.z << "), " << p_.frequency << " Hz transitions, " << p_.pause << " s pauses, period "
    << period() << " s";
  return o.str();
}

}  // namespace grainscale::dem
