#include "dem/insertion.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "dem/input_error.hpp"

namespace grainscale::dem {

namespace {

/// Spatial hash of placed spheres (set-up only, so plain containers are fine).
class PlacementGrid {
 public:
  explicit PlacementGrid(double cell) : cell_(cell) {}
  bool overlaps(const Vec3& x, double r, const std::vector<Vec3>& xs, const std::vector<double>& rs) const {
    const long cx = key(x.x), cy = key(x.y), cz = key(x.z);
    for (long dz = -1; dz <= 1; ++dz)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(hash(cx + dx, cy + dy, cz + dz));
          if (it == cells_.end()) continue;
          for (std::size_t k : it->second) {
            const double s = r + rs[k];
            if (norm2(xs[k] - x) < s * s) return true;
          }
        }
    return false;
  }
  void add(const Vec3& x, std::size_t k) { cells_[hash(key(x.x), key(x.y), key(x.z))].push_back(k); }

 private:
  long key(double v) const { return static_cast<long>(std::floor(v / cell_)); }
  static std::uint64_t hash(long a, long b, long c) {
    return (static_cast<std::uint64_t>(a) * 73856093u) ^ (static_cast<std::uint64_t>(b) * 19349663u) ^
           (static_cast<std::uint64_t>(c) * 83492791u);
  }
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

}  // namespace

Quat random_orientation(Random& rng) {
  const double u1 = rng.uniform(), u2 = 2 * std::numbers::pi * rng.uniform(), u3 = 2 * std::numbers::pi * rng.uniform();
  const double a = std::sqrt(1 - u1), c = std::sqrt(u1);
  return normalized({a * std::sin(u2), a * std::cos(u2), c * std::sin(u3), c * std::cos(u3)});
}

InsertionReport insert_particles(Simulation& sim, const ParticleBatch& b, Random& rng) {
  // Bounding radius of one particle about its centre of mass, and the clump's mass.
  double clump_bound = 0, clump_mass = 0;
  const double density = b.density > 0 ? b.density : sim.materials()[b.material].density;
  if (b.shape) {
    const MassProperties mp = union_mass_properties(b.shape->spheres);
    for (const auto& c : b.shape->spheres) clump_bound = std::max(clump_bound, norm(c.center - mp.centroid) + c.radius);
    clump_mass = density * mp.volume;
  }
  const double r_mean = 0.5 * b.diameter;
  const double r_max = b.shape ? clump_bound : r_mean * (1 + b.diameter_spread);
  const Vec3 lo = b.region_min, hi = b.region_max;
  const double vol = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
  if (hi.x - lo.x < 2 * r_max || hi.y - lo.y < 2 * r_max || hi.z - lo.z < 2 * r_max) {
    throw InputError(b.label + ": region is narrower than the largest particle (" + std::to_string(2 * r_max) + " m across)");
  }

  // Everything already in the simulation counts as an obstacle (its spheres).
  std::vector<Vec3> xs(sim.particles().x);
  std::vector<double> rs(sim.particles().radius);
  double r_all_max = r_max;
  for (double r : rs) r_all_max = std::max(r_all_max, r);
  PlacementGrid grid(2 * r_all_max);
  for (std::size_t k = 0; k < xs.size(); ++k) grid.add(xs[k], k);

  InsertionReport report;
  const std::uint64_t max_failures = 20000;
  std::uint64_t failures = 0;
  auto done = [&] { return b.count > 0 ? report.placed >= b.count : report.mass >= b.mass; };
  while (!done()) {
    const double r = b.shape ? clump_bound : r_mean * (1 + b.diameter_spread * (2 * rng.uniform() - 1));
    const Vec3 x{rng.uniform(lo.x + r, hi.x - r), rng.uniform(lo.y + r, hi.y - r), rng.uniform(lo.z + r, hi.z - r)};
    const Quat q = b.shape ? random_orientation(rng) : Quat{};
    if (grid.overlaps(x, r, xs, rs)) {
      if (b.best_effort && ++failures > max_failures / 20) {
        report.full = true;
        return report;
      }
      if (!b.best_effort && ++failures > max_failures) {
        std::ostringstream s;
        s << b.label << ": the region holds only " << report.placed << " non-overlapping particles (solid fraction "
          << (report.mass / density) / vol * 100 << " %) and more are requested; random insertion jams near 38 % "
          << "of bounding spheres. Enlarge the region (e.g. make it taller: the particles settle under gravity).";
        throw InputError(s.str());
      }
      continue;
    }
    failures = 0;
    xs.push_back(x);
    rs.push_back(r);
    grid.add(x, xs.size() - 1);
    if (b.shape) {
      sim.add_clump(*b.shape, b.material, density, x, q, b.velocity);
      report.mass += clump_mass;
    } else {
      sim.add_sphere(b.material, r, x, b.velocity);
      report.mass += density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    }
    ++report.placed;
  }
  return report;
}

}  // namespace grainscale::dem
