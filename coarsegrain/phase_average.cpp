#include "coarsegrain/phase_average.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainscale::cg {

PhaseAverage::PhaseAverage(int bins) {
  if (bins < 1) throw std::invalid_argument("phase average needs at least one bin");
  sums_.resize(static_cast<std::size_t>(bins));
}

int PhaseAverage::bin_of(double phase) const {
  if (!std::isfinite(phase)) throw std::invalid_argument("phase must be finite");
  const double frac = phase - std::floor(phase);  // in [0, 1)
  return std::min(bins() - 1, static_cast<int>(frac * bins()));
}

void PhaseAverage::add(double phase, const Moments& m) { sums_[static_cast<std::size_t>(bin_of(phase))].add(m); }

Moments PhaseAverage::average(int b) const {
  Moments m = sums_[static_cast<std::size_t>(b)];
  m.average();
  return m;
}

}  // namespace grainscale::cg
