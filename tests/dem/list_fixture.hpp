#pragma once
// Build a neighbour list for hand-placed particles the way Simulation::rebuild does: sort by cell,
// renumber the particles, build.
#include "dem/neighbor_list.hpp"
#include "dem/particles.hpp"

namespace grainscale::dem::testing {

inline void build_list(NeighborList& nl, Particles& p, double skin) {
  const auto order = nl.sort_by_cell(p, skin);
  p.permute(order);
  nl.build(p, skin, order);
}

}  // namespace grainscale::dem::testing
