#pragma once
// The regular grid fields are computed on, in the container frame: an axis-aligned box [lo, hi]
// (normally the container's inside) cut into cells. x runs along the container's length, y across
// its width, z up.
//
//   dimension 1: cells along x only; each cell spans the whole width and height (fields averaged over y, z)
//   dimension 2: cells along x and z; each spans the whole width (fields averaged over y)
//   dimension 3: cells along x, y and z
//
// An averaged axis has one cell that spans the box; a density there is mass per cell volume, i.e.
// the average over that axis. Cell (i, j, k) is stored at i + nx (j + ny k): x fastest, then y, z,
// which is C order for an array of shape (nz, ny, nx) as written to HDF5 and XDMF.
#include <array>
#include <cstddef>

#include "dem/vec3.hpp"

namespace grainscale::cg {

struct Grid {
  int dimension = 3;
  dem::Vec3 lo, hi;
  std::array<int, 3> cells{1, 1, 1};  // per axis x, y, z; 1 on averaged axes

  /// A grid of `dimension` 1, 2 or 3 over [lo, hi] with `cells` per axis; the counts of averaged
  /// axes are ignored (set to 1). Throws std::invalid_argument for an empty box or a count < 1.
  static Grid make(int dimension, dem::Vec3 lo, dem::Vec3 hi, std::array<int, 3> cells);

  /// Whether fields vary along `axis` (0 = x, 1 = y, 2 = z).
  bool resolved(int axis) const { return axis == 0 || (axis == 2 && dimension >= 2) || (axis == 1 && dimension == 3); }
  double lower(int axis) const { return lo[axis]; }
  double upper(int axis) const { return hi[axis]; }
  double spacing(int axis) const { return (hi[axis] - lo[axis]) / cells[static_cast<std::size_t>(axis)]; }
  double edge(int axis, int i) const { return i == cells[static_cast<std::size_t>(axis)] ? hi[axis] : lo[axis] + i * spacing(axis); }
  double centre(int axis, int i) const { return lo[axis] + (i + 0.5) * spacing(axis); }
  double cell_volume() const { return spacing(0) * spacing(1) * spacing(2); }
  std::size_t size() const {
    return static_cast<std::size_t>(cells[0]) * static_cast<std::size_t>(cells[1]) * static_cast<std::size_t>(cells[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(cells[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(cells[1]) * static_cast<std::size_t>(k));
  }
  bool contains(const dem::Vec3& p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
};

}  // namespace grainscale::cg
