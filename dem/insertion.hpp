#pragma once
// Filling a region with non-overlapping spheres by random sequential addition: candidate positions
// are drawn uniformly, rejected if they overlap a sphere already placed (checked through a hash grid),
// until the requested count or mass is reached. It jams near 38 % solid fraction (Torquato 2002), so
// regions are sized for the loose "rain" that then settles under gravity, as EDEM's factories do.
#include <cstdint>
#include <string>

#include "dem/random.hpp"
#include "dem/simulation.hpp"

namespace grainscale::dem {

struct SphereBatch {
  std::string label;             // for error messages, e.g. "particles[0]"
  int material = 0;
  double diameter = 0;           // m, mean
  double diameter_spread = 0;    // relative half-width of a uniform size distribution
  std::uint64_t count = 0;       // number to insert, or 0 to insert by mass
  double mass = 0;               // kg to insert when count == 0
  Vec3 region_min, region_max;   // the spheres lie entirely inside this box
  Vec3 velocity;
};

/// Insert the batch; returns the number of spheres added. Throws InputError if the region cannot
/// hold them (with the solid fraction that was requested).
std::uint64_t insert_spheres(Simulation& sim, const SphereBatch& batch, Random& rng);

}  // namespace grainscale::dem
