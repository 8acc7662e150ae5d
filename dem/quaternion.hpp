#pragma once
// Unit quaternion (w, x, y, z) for body orientation: body frame -> world frame.
#include <cmath>

#include "dem/vec3.hpp"

namespace grainscale::dem {

struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

inline Quat operator*(const Quat& a, const Quat& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
          a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

/// Whether q is a unit quaternion (an orientation) to within 1e-9 in its squared norm; false for NaN.
inline bool is_unit(const Quat& q) {
  const double q2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  return std::abs(q2 - 1) < 1e-9;
}

inline Quat normalized(const Quat& q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

/// Rotation by `angle` (rad) about the unit vector `axis`.
inline Quat axis_angle(const Vec3& axis, double angle) {
  const double s = std::sin(0.5 * angle);
  return {std::cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s};
}

inline Quat conjugate(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }

/// v' = q v q*  (body -> world). Always inlined: GCC kept it out of line in the per-sphere drift
/// loop, where the call cost 5 % of a clump-bed step (perf; docs/performance.md).
[[gnu::always_inline]] inline Vec3 rotate(const Quat& q, const Vec3& v) {
  const Vec3 u{q.x, q.y, q.z};
  const Vec3 t = 2.0 * cross(u, v);
  return v + q.w * t + cross(u, t);
}

}  // namespace grainscale::dem
