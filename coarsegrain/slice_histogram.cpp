#include "coarsegrain/slice_histogram.hpp"

#include <limits>

namespace grainscale::cg {

SliceHistogram slice_histogram(const CgParticles& p, const SpeciesTable& species, const Slices& slices) {
  const auto n = static_cast<std::size_t>(slices.count());
  SliceHistogram h{slices, std::vector<double>(n, 0.0), std::vector<double>(n, 0.0), {}, {}, {}, 0, 0, 0};
  for (std::size_t b = 0; b < p.body_position.size(); ++b) {
    const int s = slices.of(p.body_position[b].x);
    if (s < 0) {
      ++h.outside;
      continue;
    }
    const bool chaff = species.chaff[static_cast<std::size_t>(p.body_species[b])];
    (chaff ? h.chaff_bodies : h.grain_bodies)[static_cast<std::size_t>(s)] += 1;
    (chaff ? h.chaff_total : h.grain_total) += 1;
  }
  std::vector<double> chaff_volume(n, 0.0), volume(n, 0.0);
  for (std::size_t k = 0; k < p.size(); ++k) {
    const int s = slices.of(p.position[k].x);
    if (s < 0) continue;
    volume[static_cast<std::size_t>(s)] += p.volume[k];
    if (species.chaff[static_cast<std::size_t>(p.species[k])]) chaff_volume[static_cast<std::size_t>(s)] += p.volume[k];
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t s = 0; s < n; ++s) {
    h.chaff_percent.push_back(h.chaff_total > 0 ? 100.0 * h.chaff_bodies[s] / h.chaff_total : nan);
    const double all = h.chaff_bodies[s] + h.grain_bodies[s];
    h.chaff_number_fraction.push_back(all > 0 ? h.chaff_bodies[s] / all : nan);
    h.chaff_volume_fraction.push_back(volume[s] > 0 ? chaff_volume[s] / volume[s] : nan);
  }
  return h;
}

}  // namespace grainscale::cg
