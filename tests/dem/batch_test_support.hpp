#pragma once
// Shared by the tests of the vectorised contact batches (test_pair_batch.cpp, test_wall_batch.cpp):
// bitwise comparison, the Coulomb limit, and each rolling model's parameters from one pair's properties.
#include <cstring>

#include "dem/contact/rolling_constant_torque.hpp"
#include "dem/contact/rolling_epsd.hpp"
#include "dem/contact/rolling_none.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem::testing {

inline bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Is a contact force f (normal direction `normal`, any length) at the Coulomb limit, sliding?
inline bool sliding(const Vec3& f, const Vec3& normal, double friction) {
  const Vec3 n = (1.0 / norm(normal)) * normal;
  const double fn = dot(f, n);
  return norm(f - fn * n) > 0.999 * friction * (fn > 0 ? fn : 0.0);
}

template <class Rolling>
typename Rolling::Params rolling_params(const PairProperties& pp);
template <>
inline NoRolling::Params rolling_params<NoRolling>(const PairProperties& pp) { return NoRolling::make(pp); }
template <>
inline ConstantTorqueRolling::Params rolling_params<ConstantTorqueRolling>(const PairProperties& pp) {
  return ConstantTorqueRolling::make(pp);
}
template <>
inline EpsdRolling::Params rolling_params<EpsdRolling>(const PairProperties& pp) {
  return EpsdRolling::make(pp, 2.25, 0.3);
}

}  // namespace grainscale::dem::testing
