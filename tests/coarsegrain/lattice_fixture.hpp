#pragma once
// A simple cubic lattice filling a box, with cells of two lattice spacings whose edges lie on
// lattice mid-planes. That makes coarse-grained lattice fields exact: each cell integral of a
// periodic sum of kernels over one period (or two) is the period's share of the total whatever the
// kernel, and the particles around a cell centre are symmetric about it. A wall of the box sits half
// a spacing from the first lattice plane, so a reflected kernel continues the lattice exactly.
#include <array>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/grid.hpp"
#include "synthetic_snapshot.hpp"

namespace grainscale::cg::test {

struct Lattice {
  static constexpr double a = 0.005;   // spacing, m
  static constexpr double r = 0.002;   // sphere radius
  static constexpr double rho = 1380;  // sphere density
  static constexpr int nx = 40, ny = 12, nz = 12;
  static constexpr dem::Vec3 lo{0, 0, 0}, hi{nx * a, ny * a, nz * a};

  static double mass() { return rho * 4.0 / 3.0 * kPi * r * r * r; }
  static double density() { return mass() / (a * a * a); }
  static double volume_fraction() { return 4.0 / 3.0 * kPi * r * r * r / (a * a * a); }
  static Grid grid(int dimension) { return Grid::make(dimension, lo, hi, {nx / 2, ny / 2, nz / 2}); }
  /// Whether cell (i, j, k)'s kernel support (half-width `reach`) stays inside the box on resolved axes.
  static bool away_from_walls(const Grid& g, std::array<int, 3> ijk, double reach) {
    for (int ax = 0; ax < 3; ++ax) {
      if (!g.resolved(ax)) continue;
      const double c = g.centre(ax, ijk[static_cast<std::size_t>(ax)]), h = 0.5 * g.spacing(ax);
      if (c - h - reach < g.lower(ax) || c + h + reach > g.upper(ax)) return false;
    }
    return true;
  }

  template <class VelocityField>
  static dem::Snapshot snapshot(VelocityField v, std::vector<std::string> materials = {"wheat"}, int material = 0) {
    dem::Snapshot s = empty_snapshot(std::move(materials));
    add_lattice(s, material, r, rho, {0.5 * a, 0.5 * a, 0.5 * a}, a, nx, ny, nz, v);
    return s;
  }
};

}  // namespace grainscale::cg::test
