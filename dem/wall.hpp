#pragma once
// A wall is a geometry plus a pose plus, optionally, a motion: the geometry answers "which of my
// features touch this sphere?" in its own body frame, the pose carries points and velocities between
// body and world frames, and a motion profile (dem/motion_profile.hpp) moves the pose each step. A
// new geometry is one class implementing WallGeometry; a new motion one implementing MotionProfile.
#include <cstdint>
#include <memory>
#include <string>

#include "dem/motion_profile.hpp"
#include "dem/quaternion.hpp"
#include "dem/uninitialized_array.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

/// One feature of a wall geometry near a sphere, in the geometry's body frame.
struct WallHit {
  Vec3 normal;          // unit vector from the wall surface towards the sphere centre
  double distance = 0;  // distance from the surface to the sphere centre (contact if < radius)
  int feature = 0;      // stable id of the face/edge/vertex, keys the tangential history
};

class WallGeometry {
 public:
  virtual ~WallGeometry() = default;
  /// Append to `hits` (capacity `cap`) every feature whose distance to `p` is below `reach`;
  /// return how many were written. Must not double-count a contact shared by adjacent features.
  virtual int nearby(const Vec3& p, double reach, WallHit* hits, int cap) const = 0;

  /// A sphere's note of its last query, which the caller keeps per sphere for the geometries that
  /// use one (uses_hints()) and sets to kNoHint whenever the sphere's slot may hold another sphere.
  /// With it a geometry may skip a lookup whose answer has not changed since (MeshGeometry: the
  /// record of the cell the sphere is in, a load scattered over its grid, a third of its queries'
  /// time in the platform box). The hits are the same with or without it.
  using Hint = std::uint64_t;
  static constexpr Hint kNoHint = ~Hint{0};
  virtual bool uses_hints() const { return false; }
  /// nearby(), reading and updating the sphere's hint.
  virtual int nearby(const Vec3& p, double reach, WallHit* hits, int cap, Hint& /*hint*/) const {
    return nearby(p, reach, hits, cap);
  }
  /// Axis-aligned bounds in the body frame (used for domain checks and output).
  virtual void bounds(Vec3& lo, Vec3& hi) const = 0;
  virtual std::string describe() const = 0;
  /// May the tangential history of a contact on feature `from` carry over to `to` when the sphere
  /// slides from one to the other in one step (adjacent mesh triangles)? Default: no.
  virtual bool continues(int /*from*/, int /*to*/) const { return false; }
};

/// Where the wall is and how its frame moves: x_world = origin + R(q) x_body; the surface velocity at
/// a world point p is velocity + angular_velocity x (p - origin).
struct WallPose {
  Vec3 origin;
  Quat orientation;
  Vec3 velocity;
  Vec3 angular_velocity;

  Vec3 to_body(const Vec3& p) const { return rotate(conjugate(orientation), p - origin); }
  Vec3 to_world(const Vec3& p) const { return origin + rotate(orientation, p); }
  Vec3 direction_to_world(const Vec3& d) const { return rotate(orientation, d); }
  Vec3 surface_velocity(const Vec3& p) const { return velocity + cross(angular_velocity, p - origin); }
};

/// A prescribed motion applied to a wall about a pivot (world frame, at rest): a point at x0 when
/// at rest is at pivot + d(t) + R(t) (x0 - pivot) at time t.
struct WallMotion {
  std::shared_ptr<const MotionProfile> profile;
  Vec3 pivot;
};

/// A wall contact in world coordinates.
struct WallContact {
  Vec3 normal;          // from wall to sphere centre
  double overlap = 0;   // radius - distance > 0
  Vec3 point;           // contact point on the wall surface
  int feature = 0;
};

class Wall {
 public:
  Wall(std::string name, std::shared_ptr<const WallGeometry> geometry, int material, WallPose pose = {})
      : name_(std::move(name)), geometry_(std::move(geometry)), material_(material), rest_(pose), pose_(pose) {}

  static constexpr int kMaxHits = 16;

  /// What the geometry finds near a sphere (centre c, world frame, radius r): up to
  /// min(cap, kMaxHits) hits in the wall's frame (contact() turns one into world terms).
  int hits(const Vec3& c, double r, WallHit* out, int cap) const {
    return geometry_->nearby(pose_.to_body(c), r, out, cap < kMaxHits ? cap : kMaxHits);
  }
  /// The same with the sphere's hint for this wall (WallGeometry::Hint).
  int hits(const Vec3& c, double r, WallHit* out, int cap, WallGeometry::Hint& hint) const {
    return geometry_->nearby(pose_.to_body(c), r, out, cap < kMaxHits ? cap : kMaxHits, hint);
  }
  /// Hit h of a sphere (centre c, radius r) as a contact in world coordinates.
  WallContact contact(const WallHit& h, const Vec3& c, double r) const {
    const Vec3 nw = pose_.direction_to_world(h.normal);
    return {nw, r - h.distance, c - h.distance * nw, h.feature};
  }
  /// Contacts of a sphere (centre c, radius r) with this wall; returns the count written to `out`.
  int contacts(const Vec3& c, double r, WallContact* out, int cap) const {
    UninitializedArray<WallHit, kMaxHits> found;
    const int n = hits(c, r, found.data(), cap);
    for (int k = 0; k < n; ++k) out[k] = contact(found[k], c, r);
    return n;
  }

  const std::string& name() const { return name_; }
  const WallGeometry& geometry() const { return *geometry_; }
  int material() const { return material_; }
  const WallPose& pose() const { return pose_; }
  void set_pose(const WallPose& p) { pose_ = rest_ = p; }

  /// Give the wall a prescribed motion (relative to its pose at rest, which is its current pose).
  void set_motion(WallMotion m) { motion_ = std::move(m); }
  bool moving() const { return motion_.profile != nullptr; }
  const WallMotion& motion() const { return motion_; }
  /// Motion phase in [0, 1) at the last move_to (0 without a motion).
  double phase() const { return phase_; }

  /// Put the wall where its motion has it at time t: origin = pivot + d + R (o_rest - pivot),
  /// orientation = R q_rest, and the body-frame origin moves with d' + omega x (origin - pivot - d).
  void move_to(double t) {
    if (!motion_.profile) return;
    pose_ = pose_at(t, &phase_);
  }
  /// Where move_to(t) would put the wall (its pose now, without a motion), leaving it where it is;
  /// `phase`, if given, receives the motion's phase then.
  WallPose pose_at(double t, double* phase = nullptr) const {
    if (!motion_.profile) return pose_;
    const RigidMotionState s = motion_.profile->at(t);
    const Vec3 arm = rotate(s.rotation, rest_.origin - motion_.pivot);
    WallPose p;
    p.origin = motion_.pivot + s.displacement + arm;
    p.orientation = s.rotation * rest_.orientation;
    p.angular_velocity = s.angular_velocity;
    p.velocity = s.velocity + cross(s.angular_velocity, arm);
    if (phase) *phase = s.phase;
    return p;
  }

 private:
  std::string name_;
  std::shared_ptr<const WallGeometry> geometry_;
  int material_;
  WallPose rest_, pose_;
  WallMotion motion_;
  double phase_ = 0;
};

}  // namespace grainscale::dem
