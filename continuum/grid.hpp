#pragma once
// Terrain-following finite-volume grid over the bed cross-section (x = length, z = height, averaged
// over the width). The bed lies between the floor z = 0 and the free surface z = h(x); each of the
// nx columns is split into nz layers of equal fraction dσ of the local depth (σ = z / h ∈ [0, 1]).
//
// h is piecewise linear between its values at the column faces (nodes), so every cell is a
// trapezoid with two vertical sides (x-faces) and two straight sloping sides (σ-faces). Cell areas,
// face lengths and face normals below are exact for that geometry (docs/continuum.md, "Grid").
//
// With a moving free surface (flow.hpp) the grid at time t has the surface nodes h(x_f, t) and column
// depths taken from the integrated column areas (model.hpp), which differ from the trapezoid average
// of the nodes by O(dx²): the areas are what the geometric conservation law needs, the nodes what
// the face geometry needs. A grid built from nodes alone has the trapezoid depths.
//
// Unknowns are ordered column by column, index(i, k) = i * nz + k, so the semi-discrete system has a
// band Jacobian of half-width O(nz) (nz is the short direction of a bed).
#include <cstddef>
#include <span>
#include <vector>

namespace grainscale::continuum {

class Grid {
 public:
  /// `surface_nodes` holds h at x = 0, dx, ..., length (nx + 1 values, all > 0).
  Grid(double length, int nx, int nz, std::vector<double> surface_nodes);
  /// Same, with the mean depth of each column given (nx values > 0) instead of (h_i + h_{i+1}) / 2.
  Grid(double length, int nx, int nz, std::vector<double> surface_nodes, std::vector<double> column_depths);
  /// Flat bed of uniform depth.
  static Grid flat(double length, double depth, int nx, int nz);

  int nx() const { return nx_; }
  int nz() const { return nz_; }
  std::size_t cells() const { return static_cast<std::size_t>(nx_) * nz_; }
  std::size_t index(int i, int k) const { return static_cast<std::size_t>(i) * nz_ + k; }
  double length() const { return length_; }
  double dx() const { return dx_; }
  double dsigma() const { return dsigma_; }

  /// x of column face f (0..nx).
  double x_face(int f) const { return f * dx_; }
  double x_centre(int i) const { return (i + 0.5) * dx_; }
  /// Free-surface height at column face f, and the mean depth of column i (area / dx).
  double h_node(int f) const { return h_[f]; }
  double h_column(int i) const { return depth_[i]; }
  const std::vector<double>& surface_nodes() const { return h_; }
  const std::vector<double>& column_depths() const { return depth_; }
  /// dh/dx: exact on column i; centred at interior nodes, one-sided at the walls.
  double slope_column(int i) const { return (h_[i + 1] - h_[i]) / dx_; }
  double slope_node(int f) const;
  /// σ of layer face m (0..nz) and of layer centre k.
  double sigma_face(int m) const { return m * dsigma_; }
  double sigma_centre(int k) const { return (k + 0.5) * dsigma_; }
  /// Cell centre (x_i, σ_k h̄_i): within O(dx²) of the trapezoid's centroid.
  double z_centre(int i, int k) const { return sigma_centre(k) * h_column(i); }
  /// Cell area [m²] (per unit width): dσ dx h̄_i, the exact trapezoid area for trapezoid depths.
  double area(int i, int k) const { (void)k; return dsigma_ * dx_ * h_column(i); }
  /// Total bed area [m²].
  double total_area() const;

  /// Sum of area × value over all cells (e.g. chaff "mass" per unit width, m² of chaff volume fraction).
  double integrate(std::span<const double> cell_values) const;

 private:
  double length_;
  int nx_, nz_;
  double dx_, dsigma_;
  std::vector<double> h_;
  std::vector<double> depth_;  // per column
};

}  // namespace grainscale::continuum
