#include "coarsegrain/container_frame.hpp"

#include "dem/input_error.hpp"

namespace grainscale::cg {

ContainerPose container_pose(const dem::Snapshot& snap, const std::string& wall) {
  if (wall.empty()) return {};
  std::string names;
  for (const auto& w : snap.walls) {
    if (w.name == wall) return {w.origin, dem::normalized(w.orientation), w.velocity, w.angular_velocity};
    names += (names.empty() ? "" : ", ") + w.name;
  }
  throw InputError("container wall '" + wall + "' is not in the snapshot (scenario '" + snap.scenario_name +
                   "', t = " + std::to_string(snap.time) + " s); its walls are: " + (names.empty() ? "none" : names));
}

Vec3 to_container_position(const ContainerPose& pose, const Vec3& x_world) {
  return dem::rotate(dem::conjugate(pose.orientation), x_world - pose.origin);
}

Vec3 to_container_velocity(const ContainerPose& pose, const Vec3& x_world, const Vec3& v_world) {
  const Vec3 frame_velocity = pose.velocity + cross(pose.angular_velocity, x_world - pose.origin);
  return dem::rotate(dem::conjugate(pose.orientation), v_world - frame_velocity);
}

Vec3 to_world_position(const ContainerPose& pose, const Vec3& x_container) {
  return pose.origin + dem::rotate(pose.orientation, x_container);
}

Vec3 to_world_velocity(const ContainerPose& pose, const Vec3& x_container, const Vec3& v_container) {
  const Vec3 r = dem::rotate(pose.orientation, x_container);
  return dem::rotate(pose.orientation, v_container) + pose.velocity + cross(pose.angular_velocity, r);
}

}  // namespace grainscale::cg
