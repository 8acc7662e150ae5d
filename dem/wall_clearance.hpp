#pragma once
// Particles are placed clear of the walls. One that starts inside a wall (an insertion region that
// reaches outside the container, a container narrower than the particles, a pour region that a moving
// wall sweeps through) would be shot out by its first contact force, and the run would stop with a
// blow-up far from the cause; checking right after placement names the cause instead.
#include <cstdint>
#include <string>

#include "dem/simulation.hpp"

namespace grainscale::dem {

/// The deepest overlap with any wall, where the walls are now, of the spheres in slots [first, size()).
struct WallOverlap {
  double ratio = 0;        // overlap / sphere radius; 0 if none
  std::int64_t slot = -1;  // the sphere's slot
  int wall = -1;           // index into Simulation::walls()
};
WallOverlap deepest_wall_overlap(const Simulation& sim, std::size_t first);

/// Overlaps up to this fraction of the radius are rounding, not an input error.
inline constexpr double kPlacementOverlapTolerance = 1e-3;

/// Throw InputError, starting with `label` (file: key), if a sphere in slots [first, size()) overlaps a
/// wall by more than kPlacementOverlapTolerance of its radius: where it is, which wall, by how much.
void require_clear_of_walls(const Simulation& sim, std::size_t first, const std::string& label);

}  // namespace grainscale::dem
