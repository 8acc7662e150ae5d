#pragma once
// What a contact model sees of one contact: geometry and relative motion at the contact point,
// plus the history it owns. The neighbour loop (dem/force_field.cpp) fills these once for every
// pair and wall contact; the models below never look at particle arrays.
#include "dem/vec3.hpp"

namespace grainscale::dem {

struct ContactKinematics {
  Vec3 n;                 // unit normal, pointing from body j (or the wall) towards body i
  double overlap = 0;     // delta > 0 when in contact
  Vec3 v_rel;             // velocity of i's material point at the contact minus j's
  Vec3 omega_i, omega_j;  // angular velocities (world frame); omega_j of a wall is the wall's
  double lever_i = 0;     // distance from i's centre to the contact point
  double lever_j = 0;     // same for j (0 for a wall)
  double r_eff = 0;       // R* = R_i R_j / (R_i + R_j); R_i for a wall
  double m_eff = 0;       // m* = m_i m_j / (m_i + m_j); m_i for a wall
  double mass_i = 0, mass_j = 0;        // m_j = +inf for a wall
  double inertia_i = 0, inertia_j = 0;  // moments of inertia about the centre; +inf for a wall
  double dt = 0;
};

/// Per-contact state that survives between steps (and neighbour-list rebuilds).
struct ContactHistory {
  Vec3 shear;    // accumulated tangential displacement (Mindlin spring), m
  Vec3 rolling;  // elastic rolling torque of the EPSD spring, N m
};

/// What the normal/tangential model hands on to the rolling model.
struct ContactForce {
  Vec3 force;         // total force on i (normal + tangential)
  Vec3 tangential;    // tangential part of `force`
  double normal = 0;  // signed normal force on i along n (elastic + damping), N
  double stiffness = 0;  // current normal contact stiffness dF/d(delta), N/m
};

/// Keep a history vector in the current tangent plane without changing its length: the contact
/// frame turns with the bodies, so a stored displacement must turn with it (Luding 2008, Sec. 3.2).
/// (Branch-free, the same values as "if (before == 0) return; h -= (h.n) n; if (after > 0) h *= ...",
/// so that a batch of contacts vectorises: dem/pair_batch.hpp.)
inline void project_to_tangent_plane(Vec3& h, const Vec3& n) {
  const double before = norm2(h);
  const Vec3 in_plane = h - dot(h, n) * n;
  const double after = norm2(in_plane);
  const Vec3 scaled = std::sqrt(before / after) * in_plane;  // not kept unless after > 0
  h = select(before == 0, h, select(after > 0, scaled, in_plane));
}

}  // namespace grainscale::dem
