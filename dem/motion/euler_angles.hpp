#pragma once
// Roll, pitch and yaw (and their rates) to a rotation with consistent angular velocity and
// acceleration. Convention (ship motion, e.g. ITTC/SNAME; Fossen, "Handbook of Marine Craft
// Hydrodynamics and Motion Control", 2011, eq. 2.18): R = Rz(yaw) Ry(pitch) Rx(roll), roll about x
// (the container's length for a ship's hold: ships roll about their long axis), pitch about y,
// yaw about z, all in the fixed (world) frame's axes as composed.
//
// World-frame angular velocity of R = Rz(psi) Ry(theta) Rx(phi):
//   omega = psi' z + theta' Rz y + phi' Rz Ry x
// and its derivative, differentiating each rotating axis (d/dt (Q a) = omega_Q x (Q a)):
//   alpha = psi'' z + theta'' Rz y + theta' (psi' z) x (Rz y)
//         + phi'' Rz Ry x + phi' (psi' z + theta' Rz y) x (Rz Ry x)
#include "dem/motion_profile.hpp"

namespace grainscale::dem {

struct EulerAngles {
  Vec3 angle;         // roll, pitch, yaw (rad)
  Vec3 rate;          // their first derivatives
  Vec3 acceleration;  // their second derivatives
};

inline void set_rotation(const EulerAngles& e, RigidMotionState& s) {
  const Vec3 ex{1, 0, 0}, ey{0, 1, 0}, ez{0, 0, 1};
  const Quat qz = axis_angle(ez, e.angle.z), qy = axis_angle(ey, e.angle.y), qx = axis_angle(ex, e.angle.x);
  s.rotation = qz * qy * qx;
  const Vec3 y1 = rotate(qz, ey);         // pitch axis after yaw
  const Vec3 x2 = rotate(qz * qy, ex);    // roll axis after yaw and pitch
  const Vec3 w_yaw = e.rate.z * ez;
  const Vec3 w_yaw_pitch = w_yaw + e.rate.y * y1;
  s.angular_velocity = w_yaw_pitch + e.rate.x * x2;
  s.angular_acceleration = e.acceleration.z * ez + e.acceleration.y * y1 + e.rate.y * cross(w_yaw, y1) +
                           e.acceleration.x * x2 + e.rate.x * cross(w_yaw_pitch, x2);
}

}  // namespace grainscale::dem
