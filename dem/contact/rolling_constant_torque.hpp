#pragma once
// Constant directional torque (CDT) rolling resistance, EDEM's "standard rolling friction" model
// (Ai et al. 2011, model type A; EDEM Creator documentation):
//
//   tau_i = -mu_r F_n+ R_i omega_i / |omega_i|
//
// with R_i the distance from i's centre to the contact point and omega_i i's own angular velocity;
// likewise for j. Table 1 of the source report was calibrated in EDEM with exactly this model, so its
// rolling coefficients transfer unchanged.
//
// A constant torque reverses sign with omega and would make a resting sphere chatter. Since a
// resistance can at most stop the rotation, the torque is capped at I |omega| / dt, the torque that
// brings omega to zero within one step (the cap is inactive while rolling).
#include <algorithm>
#include <cmath>

#include "dem/contact/contact_kinematics.hpp"
#include "dem/material.hpp"

namespace grainscale::dem {

struct ConstantTorqueRolling {
  /// No rolling spring: ContactHistory::rolling is neither read nor written (stays zero).
  static constexpr bool kSpring = false;
  struct Params {
    double mu_r = 0;
  };
  static Params make(const PairProperties& p) { return {p.rolling_friction}; }

  static Vec3 resist(double mu_r, double f_n, double lever, const Vec3& omega, double inertia, double dt) {
    // (Branch-free: both outcomes computed, one kept, so that a batch of contacts vectorises.)
    const double w = norm(omega);
    const double tau = std::min(mu_r * std::max(f_n, 0.0) * lever, inertia * w / dt);
    return select(w == 0 || !std::isfinite(inertia), Vec3{}, (-tau / w) * omega);
  }

  static void evaluate(const Params& p, const ContactKinematics& c, const ContactForce& f, ContactHistory&,
                       Vec3& torque_i, Vec3& torque_j) {
    torque_i = resist(p.mu_r, f.normal, c.lever_i, c.omega_i, c.inertia_i, c.dt);
    torque_j = resist(p.mu_r, f.normal, c.lever_j, c.omega_j, c.inertia_j, c.dt);
  }
};

}  // namespace grainscale::dem
