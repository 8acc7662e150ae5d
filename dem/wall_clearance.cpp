#include "dem/wall_clearance.hpp"

#include <sstream>

#include "dem/input_error.hpp"

namespace grainscale::dem {

WallOverlap deepest_wall_overlap(const Simulation& sim, std::size_t first) {
  const Particles& p = sim.particles();
  WallOverlap worst;
  for (std::size_t i = first; i < p.size(); ++i) {
    for (std::size_t w = 0; w < sim.walls().size(); ++w) {
      WallContact wc[ForceField::kWallSlots];
      const int n = sim.walls()[w].contacts(p.x[i], p.radius[i], wc, ForceField::kWallSlots);
      for (int q = 0; q < n; ++q) {
        const double ratio = wc[q].overlap / p.radius[i];
        if (ratio > worst.ratio) worst = {ratio, static_cast<std::int64_t>(i), static_cast<int>(w)};
      }
    }
  }
  return worst;
}

void require_clear_of_walls(const Simulation& sim, std::size_t first, const std::string& label) {
  const WallOverlap o = deepest_wall_overlap(sim, first);
  if (o.ratio <= kPlacementOverlapTolerance) return;
  const Particles& p = sim.particles();
  const Vec3 x = p.x[o.slot];
  std::ostringstream m;
  m << label << ": a particle placed at t = " << sim.time() << " s at (" << x.x << ", " << x.y << ", " << x.z
    << ") m (sphere radius " << p.radius[o.slot] << " m) overlaps wall '" << sim.walls()[o.wall].name() << "' by "
    << o.ratio * 100 << " % of its radius. The region must lie inside the container, a particle radius clear of "
    << "every wall (of a moving wall wherever it is when particles are placed), and the container must be wider "
    << "than the particles.";
  throw InputError(m.str());
}

}  // namespace grainscale::dem
