#pragma once
// The frame in which the neighbour list measures how far the spheres have travelled since its build.
//
// A Verlet list holds every pair closer than r_i + r_j + skin at its build and stays exact while no
// sphere has travelled skin/2 (Allen & Tildesley 2017, Sec. 5.3; dem/neighbor_list.hpp). The bound
// holds for travel measured against any rigid motion G applied to every sphere alike: if
//   |x_i - G x_i^b| <= skin/2 for every sphere i   (x^b: the positions at the build),
// then |x_i - x_j| >= |G x_i^b - G x_j^b| - skin = |x_i^b - x_j^b| - skin, G keeping distances, so
// no pair unlisted at the build can have closed its gap. The world frame is G = 1. A bed that turns
// with its container (a box on the tilting platform, a hold that rolls) travels a long way in the
// world and hardly at all in the container's own frame, where G carries a point fixed to the
// container from its place at the build to its place now:
//   G = P(t) P(t_b)^-1,   P(t): the container wall's pose (its body frame -> world).
// Measured in the world, the 800 mm platform box mid-rise (0.13 rad/s) held half again as many list
// entries as at rest (its common skin sized for the spheres' world speed, six times the floor it
// keeps in the box's frame), costing 14-19 % more per step; in the box's frame, 9-10 % faster
// (in-process A/B, docs/performance.md). The adaptive skin likewise sizes the
// list for each sphere's speed relative to the frame (Simulation::choose_skins), which is also
// where the frame is chosen, at every build: the container's if the spheres' common speed is lower
// there than in the world (a bed carried by its box), else the world's (a bed at rest, a pipe lifted
// out of a heap). The near-wall masks use the same frame (ForceField::find_near_walls).
// The choice affects cost only, never which contacts are found.
#include <cmath>

#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"
#include "dem/wall.hpp"

namespace grainscale::dem {

/// The rigid map x -> A x + b carrying a point fixed in a frame from where it was (pose `then`) to
/// where it is now (pose `now`): A = R_now R_then^T, b = o_now - A o_then. The identity is kept
/// apart so that a list measured in the world does exactly the arithmetic it always did.
struct FrameShift {
  bool identity = true;
  double a[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 b;

  static FrameShift between(const WallPose& then, const WallPose& now) {
    FrameShift s;
    s.identity = false;
    const Quat q = now.orientation * conjugate(then.orientation);
    // The rotation matrix of a unit quaternion, column by column: the images of the axes.
    const Vec3 c[3] = {rotate(q, {1, 0, 0}), rotate(q, {0, 1, 0}), rotate(q, {0, 0, 1})};
    for (int k = 0; k < 3; ++k) {
      s.a[0][k] = c[k].x, s.a[1][k] = c[k].y, s.a[2][k] = c[k].z;
    }
    s.b = now.origin - s.apply(then.origin);
    return s;
  }
  Vec3 apply(const Vec3& x) const {
    return {a[0][0] * x.x + a[0][1] * x.y + a[0][2] * x.z, a[1][0] * x.x + a[1][1] * x.y + a[1][2] * x.z,
            a[2][0] * x.x + a[2][1] * x.y + a[2][2] * x.z};
  }
  /// Where the point at x at the build is now if it is fixed in the frame, the map taken as it is
  /// (for a caller that has tested `identity` once for many points).
  Vec3 carry(const Vec3& x) const { return apply(x) + b; }
  /// The same, the identity kept apart.
  Vec3 operator()(const Vec3& x) const { return identity ? x : carry(x); }
};

/// The list's frame: the world's, or the body frame of one wall (the container), with the wall's
/// pose at the list's build. Its pose at any later time is the wall's own (`pose` below: the
/// wall's pose then; unused in the world's frame).
struct ListFrame {
  int wall = -1;      // -1: the world frame
  WallPose at_build;  // (a wall's frame only)

  bool in_wall() const { return wall >= 0; }
  /// The map G = P P(build)^-1 a sphere's travel is measured against when the wall's pose is P (the
  /// identity in the world).
  FrameShift shift_to(const WallPose& pose) const { return in_wall() ? FrameShift::between(at_build, pose) : FrameShift{}; }
  /// A world point in the frame's coordinates when the wall's pose is `pose`, and back (the
  /// identity in the world).
  Vec3 to_frame(const WallPose& pose, const Vec3& x) const { return in_wall() ? pose.to_body(x) : x; }
  Vec3 to_world(const WallPose& pose, const Vec3& y) const { return in_wall() ? pose.to_world(y) : y; }
};

}  // namespace grainscale::dem
