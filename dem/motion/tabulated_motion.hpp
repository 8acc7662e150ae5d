#pragma once
// A recorded motion (a ship's or truck's measured roll, pitch, yaw, surge, sway, heave) read from
// CSV and interpolated by natural cubic splines (dem/motion/cubic_spline.hpp), so velocity and
// acceleration are continuous. Rotations compose as in dem/motion/euler_angles.hpp.
//
// File format: a header line naming the columns with their units, exactly
//   t_s,roll_deg,pitch_deg,yaw_deg,surge_m,sway_m,heave_m
// then one row per sample, time strictly increasing, at least two rows. Lines starting with '#' and
// blank lines are skipped. Any error names the file, the line and the column.
#include <array>
#include <string>

#include "dem/motion/cubic_spline.hpp"
#include "dem/motion_profile.hpp"

namespace grainscale::dem {

class TabulatedMotion final : public MotionProfile {
 public:
  /// Throws InputError naming the file, line and column on any problem.
  static TabulatedMotion load(const std::string& csv_path);

  RigidMotionState at(double t) const override;  // clamped to the record's time span
  double period() const override { return 0; }
  std::string describe() const override;
  double start_time() const { return t0_; }
  double end_time() const { return t1_; }

 private:
  std::string file_;
  double t0_ = 0, t1_ = 0;
  std::size_t rows_ = 0;
  std::array<CubicSpline, 6> dof_;  // roll, pitch, yaw (rad), surge, sway, heave (m)
};

}  // namespace grainscale::dem
