#pragma once
// The source report's motion platform: rotation about one fixed axis, "a modified 0.1 Hz sine wave
// incorporating a 4 second pause at either end of the motion", maximum tilt 24 degrees (report,
// "Physical testing on the motion platform"). Read as: the tilt moves from +A to -A along half a
// cosine of frequency f (taking 1/(2f) = 5 s), holds for the pause, moves back, holds again:
//
//   cycle period T = 1/f + 2 pause                                   (18 s for the report)
//   t' = (t + offset) mod T:
//     [0, pause)                        theta = +A                   (hold at one end)
//     [pause, pause + h)                theta = A cos(pi (t' - pause) / h)     h = 1/(2f)
//     [pause + h, 2 pause + h)          theta = -A                   (hold at the other end)
//     [2 pause + h, T)                  theta = -A cos(pi (t' - 2 pause - h) / h)
//
// Every number is a parameter. `start` chooses how t = 0 begins: "level" (default) starts at rest
// and level and rises to +A along half a cosine over one transition time h,
//     theta = A (1 - cos(pi t / h)) / 2,   t < h,
// then runs the cycle from the start of the +A hold, so a settled bed is not jolted; "end" starts
// holding at +A. theta' is continuous throughout; theta'' jumps at the ends of each transition (as
// the real platform's command did). The phase counts from the start of the +A hold.
#include <string>

#include "dem/motion_profile.hpp"

namespace grainscale::dem {

class PlatformTilt final : public MotionProfile {
 public:
  struct Params {
    double amplitude = 0;      // A, rad (report: up to 24 degrees)
    double frequency = 0.1;    // f of the sine the transitions are cut from, Hz
    double pause = 4;          // hold at each end, s
    Vec3 axis{0, 1, 0};        // rotation axis (unit), world frame
    bool start_level = true;   // begin level and at rest, rising to +A over one transition
  };
  explicit PlatformTilt(const Params& p);

  RigidMotionState at(double t) const override;
  double period() const override { return 1 / p_.frequency + 2 * p_.pause; }
  std::string describe() const override;
  /// Tilt angle and its derivatives at t (rad, rad/s, rad/s^2).
  void angle(double t, double& theta, double& rate, double& accel) const;

 private:
  Params p_;
  double ramp_ = 0;  // duration of the initial rise from level (0 with start "end")
};

}  // namespace grainscale::dem
