#pragma once
// The container's own frame. A DEM snapshot stores world-frame positions and velocities; the fields
// the continuum stage fits are wanted in the frame that tilts with the container, so that "along the
// length" stays along the length while the platform rolls. The transform is the one documented in
// docs/snapshot_layout.md ("/walls/<name>"), with R = R(orientation) body -> world:
//
//   x_c = R^T (x - origin)
//   v_c = R^T (v - velocity - angular_velocity x (x - origin))      (velocity relative to the container)
//
// With zero pose velocity and angular velocity, v_c is just the world velocity expressed in the
// container's axes. The pose is the caller's choice: a named wall of the snapshot (the container's
// floor, say) or the identity.
#include <string>

#include "dem/quaternion.hpp"
#include "dem/snapshot.hpp"
#include "dem/vec3.hpp"

namespace grainscale::cg {

using dem::Quat;
using dem::Vec3;

/// Pose and motion of the container frame in the world. Default: the world frame itself.
struct ContainerPose {
  Vec3 origin;
  Quat orientation;  // unit quaternion, container frame -> world
  Vec3 velocity;          // of the frame origin, world frame
  Vec3 angular_velocity;  // world frame
};

/// The pose of the wall named `wall` in `snap`; an empty name gives the identity pose. Throws
/// InputError naming the snapshot's walls if there is no such wall.
ContainerPose container_pose(const dem::Snapshot& snap, const std::string& wall);

/// World position -> container frame.
Vec3 to_container_position(const ContainerPose& pose, const Vec3& x_world);
/// World velocity of a point at world position x -> velocity relative to the container, in its axes.
Vec3 to_container_velocity(const ContainerPose& pose, const Vec3& x_world, const Vec3& v_world);
/// Inverses of the two above (for tests and for writing container-frame data back into the world).
Vec3 to_world_position(const ContainerPose& pose, const Vec3& x_container);
Vec3 to_world_velocity(const ContainerPose& pose, const Vec3& x_container, const Vec3& v_container);

}  // namespace grainscale::cg
