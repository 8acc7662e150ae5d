#include "coarsegrain/slices.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainscale::cg {

Slices::Slices(double lo, double hi, double w) : x_lo(lo), x_hi(hi), width(w) {
  if (!(hi > lo) || !(w > 0) || !std::isfinite(hi - lo)) throw std::invalid_argument("slices need x_lo < x_hi and a positive width");
  n_ = std::max(1, static_cast<int>(std::ceil((hi - lo) / w - 1e-9)));
}

int Slices::of(double x) const {
  if (!(x >= x_lo && x <= x_hi)) return -1;
  return std::min(n_ - 1, static_cast<int>(std::floor((x - x_lo) / width)));
}

}  // namespace grainscale::cg
