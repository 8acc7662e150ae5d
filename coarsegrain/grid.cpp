#include "coarsegrain/grid.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace grainscale::cg {

Grid Grid::make(int dimension, dem::Vec3 lo, dem::Vec3 hi, std::array<int, 3> cells) {
  if (dimension < 1 || dimension > 3) throw std::invalid_argument("grid dimension must be 1, 2 or 3");
  Grid g;
  g.dimension = dimension;
  g.lo = lo;
  g.hi = hi;
  for (int a = 0; a < 3; ++a) {
    if (!(hi[a] > lo[a]) || !std::isfinite(hi[a] - lo[a])) {
      throw std::invalid_argument("grid box is empty along axis " + std::to_string(a) + " (need lo < hi)");
    }
    const auto s = static_cast<std::size_t>(a);
    if (!g.resolved(a)) {
      g.cells[s] = 1;
    } else {
      if (cells[s] < 1) throw std::invalid_argument("grid needs at least one cell along axis " + std::to_string(a));
      g.cells[s] = cells[s];
    }
  }
  return g;
}

}  // namespace grainscale::cg
