#pragma once
// Rotation of a rigid body with principal moments of inertia I = (I1, I2, I3).
//
// State: orientation q (principal/body frame -> world) and angular momentum L in the world frame.
// Torque kicks change L; between kicks the body rotates freely, L_world constant.
//
// Free rotation uses the symplectic splitting of Dullweber, Leimkuhler & McLachlan (1997, J. Chem.
// Phys. 107:5840), also used by NO_SQUISH (Miller et al. 2002). The kinetic energy
// T = sum_k Lb_k^2 / (2 I_k) splits into three terms, each an exact rotation about one body axis:
//     R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2),
// where Rk(t) turns the body about its axis k by phi = t Lb_k / I_k, and so turns the body-frame
// momentum Lb by -phi. Each sub-step is a rotation, so |L| is conserved to round-off; the scheme is
// symplectic and time-reversible, so the energy error stays bounded (O(h^2)) and does not drift.
// tests/dem/test_rigid_rotation.cpp checks drift over 1,000 periods and the intermediate-axis flip.
#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

/// Body-frame components of a world vector.
inline Vec3 to_body(const Quat& q, const Vec3& w) { return rotate(conjugate(q), w); }

/// Angular velocity (world frame) of a body with orientation q, world angular momentum L and
/// principal moments I: omega = R I^-1 R^T L.
inline Vec3 angular_velocity(const Quat& q, const Vec3& L, const Vec3& inertia) {
  const Vec3 lb = to_body(q, L);
  return rotate(q, {lb.x / inertia.x, lb.y / inertia.y, lb.z / inertia.z});
}

/// Rotational kinetic energy sum Lb_k^2 / (2 I_k).
inline double rotational_energy(const Quat& q, const Vec3& L, const Vec3& inertia) {
  const Vec3 lb = to_body(q, L);
  return 0.5 * (lb.x * lb.x / inertia.x + lb.y * lb.y / inertia.y + lb.z * lb.z / inertia.z);
}

namespace detail {

/// sin x and cos x. A body turns by ~1e-4 rad per sub-step, where the Taylor series to x^7 (sin)
/// and x^8 (cos) is exact to round-off (next terms < 3e-22 relative for |x| < 0.01) and costs a
/// tenth of a libm call (sincos was 6 % of a clump-bed step: docs/performance.md).
constexpr double kSeriesRange = 0.01;
inline void sin_cos_series(double x, double& s, double& c) {
  const double x2 = x * x;
  s = x * (1 - x2 * (1.0 / 6) * (1 - x2 * (1.0 / 20) * (1 - x2 * (1.0 / 42))));
  c = 1 - x2 * 0.5 * (1 - x2 * (1.0 / 12) * (1 - x2 * (1.0 / 30) * (1 - x2 * (1.0 / 56))));
}
inline void sin_cos(double x, double& s, double& c) {
  if (std::abs(x) < kSeriesRange) {
    sin_cos_series(x, s, c);
  } else {
    s = std::sin(x);
    c = std::cos(x);
  }
}

/// Exact free rotation about body axis k for time t (one term of the splitting); returns the half
/// angle turned. With `series_only`, its sine and cosine always come from the series (no branch, so
/// that a loop over bodies vectorises): exact only while the half angle is within kSeriesRange.
template <bool series_only = false>
inline double rotate_about_body_axis(int k, double t, Quat& q, Vec3& lb, const Vec3& inertia) {
  const double lk = k == 0 ? lb.x : (k == 1 ? lb.y : lb.z);
  const double ik = k == 0 ? inertia.x : (k == 1 ? inertia.y : inertia.z);
  const double phi = t * lk / ik;
  // One sine and cosine of the half angle serve both the quaternion (half angle) and the momentum
  // (double-angle formulas).
  double sh, ch;
  if constexpr (series_only) {
    sin_cos_series(0.5 * phi, sh, ch);
  } else {
    sin_cos(0.5 * phi, sh, ch);
  }
  const double c = ch * ch - sh * sh, s = 2 * sh * ch;
  // The body turns by +phi about its own axis k (q <- q * rot_k(phi)), so the fixed world momentum,
  // seen from the body, turns by -phi about that axis.
  Quat turn{ch, 0, 0, 0};
  if (k == 0) {
    turn.x = sh;
    lb = {lb.x, c * lb.y + s * lb.z, -s * lb.y + c * lb.z};
  } else if (k == 1) {
    turn.y = sh;
    lb = {c * lb.x - s * lb.z, lb.y, s * lb.x + c * lb.z};
  } else {
    turn.z = sh;
    lb = {c * lb.x + s * lb.y, -s * lb.x + c * lb.y, lb.z};
  }
  q = q * turn;
  return 0.5 * phi;
}

}  // namespace detail

/// free_rotation_isotropic's turn within the sine series' range, written without branches, so that a
/// loop over bodies vectorises (IsotropicRotationBatch; free_rotation_isotropic calls it too).
/// Returns false if the half angle is beyond the series' range: q is then not what
/// free_rotation_isotropic gives and must be recomputed with it. Without spin q is left as it was
/// (not normalised again).
inline bool free_rotation_isotropic_series(Quat& q, const Vec3& omega, double h) {
  const double w2 = norm2(omega);
  const double x2 = 0.25 * h * h * w2;
  const double sw = 0.5 * h * (1 - x2 * (1.0 / 6) * (1 - x2 * (1.0 / 20) * (1 - x2 * (1.0 / 42))));
  const double c = 1 - x2 * 0.5 * (1 - x2 * (1.0 / 12) * (1 - x2 * (1.0 / 30) * (1 - x2 * (1.0 / 56))));
  const Quat turned = normalized(Quat{c, sw * omega.x, sw * omega.y, sw * omega.z} * q);
  const bool spin = x2 > 0;
  q.w = spin ? turned.w : q.w;
  q.x = spin ? turned.x : q.x;
  q.y = spin ? turned.y : q.y;
  q.z = spin ? turned.z : q.z;
  return x2 < detail::kSeriesRange * detail::kSeriesRange;
}

/// Free rotation of an isotropic body (a sphere) for time h: omega = L / I is constant, so one exact
/// turn by |omega| h about omega (the splitting below would give the same with five; profiling showed
/// sincos at 24 % of a sphere run). Where the half angle x = |omega| h / 2 is within the series' range
/// the turn's quaternion (cos x, sin x omega / |omega|) comes from series in x^2 (sin x / x and cos x,
/// the terms of detail::sin_cos_series): no square root, division or libm call for the turn (the
/// product is normalised as before). The body loop of a settled sphere bed spent 5-7 % of its step
/// in libm's sincos (docs/performance.md).
inline void free_rotation_isotropic(Quat& q, const Vec3& omega, double h) {
  Quat turned = q;
  if (free_rotation_isotropic_series(turned, omega, h)) {  // (no spin: q as it was)
    q = turned;
    return;
  }
  // Beyond the series' range (or not finite): the half angle's sine and cosine from libm.
  const double w = std::sqrt(norm2(omega)), x = 0.5 * h * w;
  const double sw = std::sin(x) / w, c = std::cos(x);  // sin x / |omega| and cos x
  q = normalized(Quat{c, sw * omega.x, sw * omega.y, sw * omega.z} * q);
}

/// Free rotation for time h (no torque): updates q; the world angular momentum L is unchanged.
inline void free_rotation_step(Quat& q, const Vec3& L, const Vec3& inertia, double h) {
  if (inertia.x == inertia.y && inertia.y == inertia.z) {
    free_rotation_isotropic(q, (1.0 / inertia.x) * L, h);
    return;
  }
  Vec3 lb = to_body(q, L);
  detail::rotate_about_body_axis(0, 0.5 * h, q, lb, inertia);
  detail::rotate_about_body_axis(1, 0.5 * h, q, lb, inertia);
  detail::rotate_about_body_axis(2, h, q, lb, inertia);
  detail::rotate_about_body_axis(1, 0.5 * h, q, lb, inertia);
  detail::rotate_about_body_axis(0, 0.5 * h, q, lb, inertia);
  q = normalized(q);
}

/// free_rotation_step for a body that is not isotropic, written without branches so that a loop over
/// bodies vectorises (Simulation::drift). Returns false if a sub-step turned beyond the sine series'
/// range: q is then not what free_rotation_step gives and must be recomputed with it. Where it
/// returns true, q is bit for bit free_rotation_step's.
inline bool free_rotation_step_series(Quat& q, const Vec3& L, const Vec3& inertia, double h) {
  Vec3 lb = to_body(q, L);
  auto turn = [&](int axis, double t) {  // true while the half angle is within the series' range
    return std::abs(detail::rotate_about_body_axis<true>(axis, t, q, lb, inertia)) < detail::kSeriesRange;
  };
  bool in_range = turn(0, 0.5 * h);
  in_range &= turn(1, 0.5 * h);
  in_range &= turn(2, h);
  in_range &= turn(1, 0.5 * h);
  in_range &= turn(0, 0.5 * h);
  q = normalized(q);
  return in_range;
}

}  // namespace grainscale::dem
