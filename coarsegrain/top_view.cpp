#include "coarsegrain/top_view.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace grainscale::cg {

double TopView::coverage() const {
  long occupied = 0, chaff_count = 0;
  for (const std::uint8_t s : state) {
    occupied += s != empty;
    chaff_count += s == chaff;
  }
  return occupied > 0 ? static_cast<double>(chaff_count) / static_cast<double>(occupied) : std::numeric_limits<double>::quiet_NaN();
}

double TopView::occupied_fraction() const {
  if (state.empty()) return 0;
  const auto occupied = std::count_if(state.begin(), state.end(), [](std::uint8_t s) { return s != empty; });
  return static_cast<double>(occupied) / static_cast<double>(state.size());
}

namespace {

/// Calls f(pixel index, surface height) for every pixel whose centre lies in sphere k's disc.
template <class F>
void for_each_covered_pixel(const TopView& v, const dem::Vec3& c, double r, F f) {
  const int i0 = std::max(0, static_cast<int>(std::ceil((c.x - r - v.x_lo) / v.pixel - 0.5)));
  const int i1 = std::min(v.nx - 1, static_cast<int>(std::floor((c.x + r - v.x_lo) / v.pixel - 0.5)));
  const int j0 = std::max(0, static_cast<int>(std::ceil((c.y - r - v.y_lo) / v.pixel - 0.5)));
  const int j1 = std::min(v.ny - 1, static_cast<int>(std::floor((c.y + r - v.y_lo) / v.pixel - 0.5)));
  for (int j = j0; j <= j1; ++j) {
    const double dy = v.y_lo + (j + 0.5) * v.pixel - c.y;
    for (int i = i0; i <= i1; ++i) {
      const double dx = v.x(i) - c.x;
      const double h2 = r * r - dx * dx - dy * dy;
      if (h2 < 0) continue;
      f(static_cast<std::size_t>(i) + static_cast<std::size_t>(v.nx) * static_cast<std::size_t>(j), c.z + std::sqrt(h2));
    }
  }
}

}  // namespace

TopView render_top_view(const CgParticles& p, const SpeciesTable& species, const dem::Vec3& lo, const dem::Vec3& hi,
                        const TopViewSettings& settings) {
  if (!(settings.pixel > 0) || !(settings.layer_thickness >= 0)) throw std::invalid_argument("top view: pixel must be > 0, layer thickness >= 0");
  if (!(hi.x > lo.x) || !(hi.y > lo.y)) throw std::invalid_argument("top view: empty rectangle");
  TopView v;
  v.x_lo = lo.x;
  v.y_lo = lo.y;
  v.pixel = settings.pixel;
  v.nx = std::max(1, static_cast<int>(std::lround((hi.x - lo.x) / settings.pixel)));
  v.ny = std::max(1, static_cast<int>(std::lround((hi.y - lo.y) / settings.pixel)));
  const std::size_t n = static_cast<std::size_t>(v.nx) * static_cast<std::size_t>(v.ny);
  v.height.assign(n, -std::numeric_limits<double>::infinity());
  v.state.assign(n, TopView::empty);
  // Pass 1: the z-buffer of all spheres (a max, so the order of spheres does not matter).
  for (std::size_t k = 0; k < p.size(); ++k) {
    for_each_covered_pixel(v, p.position[k], p.radius[k], [&](std::size_t px, double z) {
      v.height[px] = std::max(v.height[px], z);
      v.state[px] = TopView::grain;
    });
  }
  // Pass 2: chaff spheres reaching the top layer.
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (!species.chaff[static_cast<std::size_t>(p.species[k])]) continue;
    for_each_covered_pixel(v, p.position[k], p.radius[k], [&](std::size_t px, double z) {
      if (z >= v.height[px] - settings.layer_thickness) v.state[px] = TopView::chaff;
    });
  }
  return v;
}

CoverageProfile coverage_profile(const TopView& v, const Slices& slices) {
  const auto n = static_cast<std::size_t>(slices.count());
  CoverageProfile c{slices, std::vector<double>(n), std::vector<long>(n, 0), std::vector<long>(n, 0)};
  for (int i = 0; i < v.nx; ++i) {
    const int s = slices.of(v.x(i));
    if (s < 0) continue;
    for (int j = 0; j < v.ny; ++j) {
      const std::uint8_t st = v.state[static_cast<std::size_t>(i) + static_cast<std::size_t>(v.nx) * static_cast<std::size_t>(j)];
      c.occupied_pixels[static_cast<std::size_t>(s)] += st != TopView::empty;
      c.chaff_pixels[static_cast<std::size_t>(s)] += st == TopView::chaff;
    }
  }
  for (std::size_t s = 0; s < n; ++s) {
    c.coverage[s] = c.occupied_pixels[s] > 0 ? static_cast<double>(c.chaff_pixels[s]) / static_cast<double>(c.occupied_pixels[s])
                                             : std::numeric_limits<double>::quiet_NaN();
  }
  return c;
}

}  // namespace grainscale::cg
