#include "studies/loop_motion.hpp"

#include <cmath>

#include "dem/input_error.hpp"
#include "dem/scenario.hpp"

namespace grainscale::studies {

MotionFacts motion_facts(const std::string& file, const std::string& container) {
  const dem::Scenario s = dem::load_scenario(file);
  const dem::WallSpec* wall = nullptr;
  for (const auto& w : s.walls) {
    if (container.empty() ? w.motion.profile != nullptr : w.name == container) {
      wall = &w;
      break;
    }
  }
  if (!wall) {
    throw InputError(file + ": " + (container.empty() ? std::string("no moving wall (the container's motion is needed)")
                                                      : "no wall named '" + container + "'"));
  }
  if (!wall->motion.profile) throw InputError(file + ": wall '" + wall->name + "' does not move");
  const dem::MotionProfile& m = *wall->motion.profile;
  if (!(m.period() > 0)) throw InputError(file + ": the motion of wall '" + wall->name + "' is not periodic (" + m.describe() + ")");
  MotionFacts f = cycle_facts(m);
  f.container = wall->name;
  const dem::Vec3 pivot = wall->pose.to_body(wall->motion.pivot);
  f.axis_x = pivot.x;
  f.axis_z = pivot.z;
  return f;
}

MotionFacts cycle_facts(const dem::MotionProfile& m) {
  MotionFacts f;
  f.period = m.period();
  // Sample one cycle well after any start-up transition.
  const int n = 3600;
  const double t0 = 10 * f.period;
  double sum = 0, sum_alpha = 0;
  int paused = 0;
  for (int j = 0; j < n; ++j) {
    const dem::RigidMotionState st = m.at(t0 + f.period * (j + 0.5) / n);
    const double w2 = dot(st.angular_velocity, st.angular_velocity);
    sum += w2;
    sum_alpha += dot(st.angular_acceleration, st.angular_acceleration);
    paused += std::sqrt(w2) < 1e-6;
    const double angle = 2 * std::acos(std::min(1.0, std::abs(st.rotation.w))) * 180 / M_PI;
    f.peak_angle_deg = std::max(f.peak_angle_deg, angle);
  }
  f.omega2_mean = sum / n;
  f.alpha2_mean = sum_alpha / n;
  f.pause_fraction = static_cast<double>(paused) / n;
  return f;
}

}  // namespace grainscale::studies
