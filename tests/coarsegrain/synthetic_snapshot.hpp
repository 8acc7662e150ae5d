#pragma once
// Hand-built snapshots for the coarse-graining tests: loose spheres (each its own body) placed where a
// test needs them, with materials by name. No DEM run, so each test states its particle set exactly.
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "dem/snapshot.hpp"

namespace grainscale::cg::test {

inline constexpr double kPi = std::numbers::pi;

/// An empty snapshot with the given materials, scale factor 1.
inline dem::Snapshot empty_snapshot(std::vector<std::string> materials, double time = 0) {
  dem::Snapshot s;
  s.layout_version = dem::kSnapshotLayoutVersion;
  s.time = time;
  s.material_names = std::move(materials);
  return s;
}

/// Append a loose sphere (a body of one sphere) of `material` index, radius r and density rho.
inline void add_sphere(dem::Snapshot& s, int material, double r, double rho, dem::Vec3 x, dem::Vec3 v = {}) {
  const std::uint64_t id = s.id.empty() ? 1 : s.id.back() + 1;
  const double m = rho * 4.0 / 3.0 * kPi * r * r * r;
  s.id.push_back(id);
  s.body.push_back(id);
  s.material.push_back(material);
  s.radius.push_back(r);
  s.mass.push_back(m);
  s.position.push_back(x);
  s.velocity.push_back(v);
  s.angular_velocity.push_back({});
  s.orientation.push_back({});
  s.body_id.push_back(id);
  s.body_shape.push_back(-1);
  s.body_mass.push_back(m);
  s.body_inertia.push_back({});
  s.body_position.push_back(x);
  s.body_velocity.push_back(v);
  s.body_angular_velocity.push_back({});
  s.body_orientation.push_back({});
}

/// Append a clump: spheres (centre, radius) of one material and density sharing one body at
/// `body_position`; each sphere carries the clump's mass shared in proportion to r^3, as in a snapshot.
inline void add_clump(dem::Snapshot& s, int material, double rho, const std::vector<std::pair<dem::Vec3, double>>& spheres,
                      dem::Vec3 body_position) {
  const std::uint64_t body = 1000000 + s.body_id.size();  // never a loose sphere's id (those are sphere ids)
  double r3 = 0;
  for (const auto& sp : spheres) r3 += sp.second * sp.second * sp.second;
  const double mass = rho * 4.0 / 3.0 * kPi * r3;  // overlaps ignored: a test clump
  for (const auto& [x, r] : spheres) {
    s.id.push_back(s.id.empty() ? 1 : s.id.back() + 1);
    s.body.push_back(body);
    s.material.push_back(material);
    s.radius.push_back(r);
    s.mass.push_back(mass * r * r * r / r3);
    s.position.push_back(x);
    s.velocity.push_back({});
    s.angular_velocity.push_back({});
    s.orientation.push_back({});
  }
  s.body_id.push_back(body);
  s.body_shape.push_back(0);
  s.body_mass.push_back(mass);
  s.body_inertia.push_back({});
  s.body_position.push_back(body_position);
  s.body_velocity.push_back({});
  s.body_angular_velocity.push_back({});
  s.body_orientation.push_back({});
}

/// A simple cubic lattice of spheres: nx x ny x nz sites with spacing a, the first site at `first`,
/// velocity from `velocity(x)`.
template <class VelocityField>
void add_lattice(dem::Snapshot& s, int material, double r, double rho, dem::Vec3 first, double a, int nx, int ny, int nz,
                 VelocityField velocity) {
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const dem::Vec3 x = first + dem::Vec3{i * a, j * a, k * a};
        add_sphere(s, material, r, rho, x, velocity(x));
      }
}

inline void add_lattice(dem::Snapshot& s, int material, double r, double rho, dem::Vec3 first, double a, int nx, int ny,
                        int nz) {
  add_lattice(s, material, r, rho, first, a, nx, ny, nz, [](const dem::Vec3&) { return dem::Vec3{}; });
}

}  // namespace grainscale::cg::test
