#pragma once
// Filling a region with non-overlapping particles by random sequential addition: candidate positions
// (and, for clumps, orientations) are drawn uniformly and rejected if the particle's bounding sphere
// overlaps one already placed (checked through a hash grid), until the requested count or mass is
// reached. It jams near 38 % solid fraction of bounding spheres (Torquato 2002), so regions are sized
// for the loose "rain" that then settles under gravity, as EDEM's factories do.
#include <cstdint>
#include <memory>
#include <string>

#include "dem/random.hpp"
#include "dem/shape.hpp"
#include "dem/simulation.hpp"

namespace grainscale::dem {

struct ParticleBatch {
  std::string label;                   // for messages, e.g. "scenario.yaml: particles[0]"
  int material = 0;
  std::shared_ptr<const Shape> shape;  // clumps of this shape; null for spheres of `diameter`
  double density = 0;                  // kg/m^3 for clumps; 0 = the material's density
  double diameter = 0;                 // m, mean (spheres)
  double diameter_spread = 0;          // relative half-width of a uniform size distribution (spheres)
  std::uint64_t count = 0;             // number to insert, or 0 to insert by mass
  double mass = 0;                     // kg to insert when count == 0
  Vec3 region_min, region_max;         // the particles lie entirely inside this box
  Vec3 velocity;
  bool best_effort = false;            // place what fits and return, instead of failing when full
};

struct InsertionReport {
  std::uint64_t placed = 0;
  double mass = 0;     // kg
  bool full = false;   // (best effort) the region had no room for the rest
};

/// Insert the batch. Throws InputError if the region cannot hold it (quoting the solid fraction),
/// unless `best_effort`: then it reports `full` and returns what it placed.
InsertionReport insert_particles(Simulation& sim, const ParticleBatch& batch, Random& rng);

/// A uniformly distributed random orientation (Shoemake 1992, Graphics Gems III).
Quat random_orientation(Random& rng);

}  // namespace grainscale::dem
