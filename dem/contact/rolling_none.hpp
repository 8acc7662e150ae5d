#pragma once
// No rolling resistance: rolling is resisted only through sliding friction at the contacts.
#include "dem/contact/contact_kinematics.hpp"

namespace grainscale::dem {

struct NoRolling {
  /// No rolling spring: ContactHistory::rolling is neither read nor written (stays zero).
  static constexpr bool kSpring = false;
  struct Params {};
  static Params make(const PairProperties&) { return {}; }
  static void evaluate(const Params&, const ContactKinematics&, const ContactForce&, ContactHistory&, Vec3& torque_i,
                       Vec3& torque_j) {
    torque_i = {};
    torque_j = {};
  }
};

}  // namespace grainscale::dem
