#include "continuum/grid.hpp"

#include <cmath>
#include <string>

#include "dem/input_error.hpp"

namespace grainscale::continuum {

Grid::Grid(double length, int nx, int nz, std::vector<double> surface_nodes)
    : length_(length), nx_(nx), nz_(nz), h_(std::move(surface_nodes)) {
  if (!(length > 0) || nx < 1 || nz < 1) {
    throw InputError("continuum grid: need length > 0, nx >= 1, nz >= 1 (got length " + std::to_string(length) +
                     ", nx " + std::to_string(nx) + ", nz " + std::to_string(nz) + ")");
  }
  if (h_.size() != static_cast<std::size_t>(nx) + 1) {
    throw InputError("continuum grid: surface needs nx + 1 = " + std::to_string(nx + 1) + " node heights, got " +
                     std::to_string(h_.size()));
  }
  for (double h : h_) {
    if (!(h > 0) || !std::isfinite(h)) throw InputError("continuum grid: surface heights must be finite and > 0");
  }
  dx_ = length / nx;
  dsigma_ = 1.0 / nz;
  depth_.resize(static_cast<std::size_t>(nx));
  for (int i = 0; i < nx; ++i) depth_[i] = 0.5 * (h_[i] + h_[i + 1]);
}

Grid::Grid(double length, int nx, int nz, std::vector<double> surface_nodes, std::vector<double> column_depths)
    : Grid(length, nx, nz, std::move(surface_nodes)) {
  if (column_depths.size() != static_cast<std::size_t>(nx)) {
    throw InputError("continuum grid: need nx = " + std::to_string(nx) + " column depths, got " +
                     std::to_string(column_depths.size()));
  }
  for (double d : column_depths) {
    if (!(d > 0) || !std::isfinite(d)) throw InputError("continuum grid: column depths must be finite and > 0");
  }
  depth_ = std::move(column_depths);
}

Grid Grid::flat(double length, double depth, int nx, int nz) {
  return Grid(length, nx, nz, std::vector<double>(static_cast<std::size_t>(nx) + 1, depth));
}

double Grid::slope_node(int f) const {
  if (nx_ == 1) return slope_column(0);
  if (f == 0) return slope_column(0);
  if (f == nx_) return slope_column(nx_ - 1);
  return (h_[f + 1] - h_[f - 1]) / (2 * dx_);
}

double Grid::total_area() const {
  double a = 0;
  for (int i = 0; i < nx_; ++i) a += dx_ * h_column(i);
  return a;
}

double Grid::integrate(std::span<const double> v) const {
  // Column by column, so the sum order (and hence round-off) is fixed.
  double total = 0;
  for (int i = 0; i < nx_; ++i) {
    double column = 0;
    for (int k = 0; k < nz_; ++k) column += v[index(i, k)];
    total += column * dsigma_ * dx_ * h_column(i);
  }
  return total;
}

}  // namespace grainscale::continuum
