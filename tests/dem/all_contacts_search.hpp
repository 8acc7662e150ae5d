#pragma once
// The contacts a bed has now, found by a search over every pair of spheres and every sphere and
// wall: what the neighbour list and the near-wall masks must let the force loop find.
#include <cstddef>

#include "dem/force_field.hpp"
#include "dem/simulation.hpp"

namespace grainscale::dem::testing {

/// Pairs of spheres of different bodies that overlap now.
inline std::size_t overlapping_pairs(const Particles& p) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double r = p.radius[i] + p.radius[j];
      n += p.body[i] != p.body[j] && norm2(p.x[i] - p.x[j]) < r * r;
    }
  return n;
}

/// Contacts of every sphere with wall `wall`.
inline std::size_t wall_contacts(const Simulation& sim, std::size_t wall) {
  std::size_t n = 0;
  const Particles& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    WallContact wc[ForceField::kWallSlots + 1];
    n += static_cast<std::size_t>(sim.walls()[wall].contacts(p.x[i], p.radius[i], wc, ForceField::kWallSlots + 1));
  }
  return n;
}

}  // namespace grainscale::dem::testing
