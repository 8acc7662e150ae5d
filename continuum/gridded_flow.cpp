#include "continuum/gridded_flow.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>

#include "dem/input_error.hpp"

namespace grainscale::continuum {

namespace {

constexpr int kSigmaSamples = 129;  // ψ tabulated at this many σ levels per data column

/// Index j and weight a with v = (1 − a) xs[j] + a xs[j + 1], clamped to the ends.
std::pair<int, double> bracket(const std::vector<double>& xs, double v) {
  if (xs.size() == 1 || v <= xs.front()) return {0, 0.0};
  if (v >= xs.back()) return {static_cast<int>(xs.size()) - 2, 1.0};
  const auto it = std::upper_bound(xs.begin(), xs.end(), v);
  const int j = static_cast<int>(it - xs.begin()) - 1;
  return {j, (v - xs[j]) / (xs[j + 1] - xs[j])};
}

std::vector<double> read_dataset(hid_t file, const std::string& path, const std::string& name,
                                 std::vector<hsize_t>& dims) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) throw InputError(path + ": missing dataset '" + name + "'");
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  const int rank = H5Sget_simple_extent_ndims(space);
  dims.assign(static_cast<std::size_t>(std::max(rank, 0)), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  hsize_t count = 1;
  for (hsize_t d : dims) count *= d;
  std::vector<double> data(count);
  const herr_t status = H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Sclose(space);
  H5Dclose(set);
  if (status < 0) throw InputError(path + ": cannot read dataset '" + name + "' as numbers");
  for (double v : data) {
    if (!std::isfinite(v)) throw InputError(path + ": dataset '" + name + "' holds a NaN or infinity");
  }
  return data;
}

}  // namespace

GriddedFlow GriddedFlow::load(const std::string& path, double length) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported as InputError below
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw InputError(path + ": cannot open as HDF5");
  try {
    std::vector<hsize_t> dx, dz, du, dr, dh;
    auto x = read_dataset(file, path, "/x", dx);
    auto z = read_dataset(file, path, "/z", dz);
    auto u = read_dataset(file, path, "/u", du);
    auto r = read_dataset(file, path, "/shear_rate", dr);
    auto h = read_dataset(file, path, "/surface_height", dh);
    H5Fclose(file);
    const std::vector<hsize_t> field{z.size(), x.size()};
    if (du != field || dr != field || h.size() != x.size()) {
      throw InputError(path + ": /u and /shear_rate must be [nz][nx] and /surface_height [nx] for /x [nx], /z [nz]");
    }
    return GriddedFlow(length, x, z, u, r, h);
  } catch (...) {
    H5Fclose(file);
    throw;
  }
}

GriddedFlow::GriddedFlow(double length, std::vector<double> x, std::vector<double> z, std::vector<double> u,
                         std::vector<double> rate, std::vector<double> h)
    : length_(length), x_(std::move(x)), z_(std::move(z)), u_(std::move(u)), rate_(std::move(rate)), h_(std::move(h)) {
  if (x_.size() < 2 || z_.size() < 2) throw InputError("gridded flow: need at least 2 x and 2 z levels");
  if (!std::is_sorted(x_.begin(), x_.end()) || !std::is_sorted(z_.begin(), z_.end()) || x_.front() <= 0 ||
      x_.back() >= length_) {
    throw InputError("gridded flow: x and z must increase, with 0 < x < L");
  }
  for (double v : h_) {
    if (!(v > 0)) throw InputError("gridded flow: surface heights must be > 0");
  }
  for (double v : rate_) {
    if (v < 0) throw InputError("gridded flow: shear rates must be >= 0");
  }
  // (G1) per data column: trapezoid rule on a fine σ grid, then the depth-mean flux removed.
  const int nxd = static_cast<int>(x_.size()), nzd = static_cast<int>(z_.size());
  psi_sigma_.assign(nxd, std::vector<double>(kSigmaSamples, 0.0));
  for (int j = 0; j < nxd; ++j) {
    auto u_at = [&](double zz) {
      const auto [k, a] = bracket(z_, zz);
      return (1 - a) * u_[static_cast<std::size_t>(k) * nxd + j] + a * u_[static_cast<std::size_t>(k + 1) * nxd + j];
    };
    const double dz = h_[j] / (kSigmaSamples - 1);
    auto& p = psi_sigma_[j];
    for (int m = 1; m < kSigmaSamples; ++m) p[m] = p[m - 1] + 0.5 * dz * (u_at((m - 1) * dz) + u_at(m * dz));
    const double q = p.back();
    for (int m = 0; m < kSigmaSamples; ++m) p[m] -= q * m / (kSigmaSamples - 1.0);
  }
  (void)nzd;
}

double GriddedFlow::column_psi(int j, double sigma) const {
  const double s = std::clamp(sigma, 0.0, 1.0) * (kSigmaSamples - 1);
  const int m = std::min(static_cast<int>(s), kSigmaSamples - 2);
  const double a = s - m;
  return (1 - a) * psi_sigma_[j][m] + a * psi_sigma_[j][m + 1];
}

double GriddedFlow::surface_height(double x) const {
  const auto [j, a] = bracket(x_, x);
  return (1 - a) * h_[j] + a * h_[j + 1];
}

double GriddedFlow::stream_function(double x, double z, double) const {
  const double sigma = z / surface_height(x);
  if (x <= x_.front()) return column_psi(0, sigma) * std::max(0.0, x) / x_.front();
  if (x >= x_.back()) return column_psi(static_cast<int>(x_.size()) - 1, sigma) * std::max(0.0, length_ - x) / (length_ - x_.back());
  const auto [j, a] = bracket(x_, x);
  return (1 - a) * column_psi(j, sigma) + a * column_psi(j + 1, sigma);
}

double GriddedFlow::shear_rate(double x, double z, double) const {
  const int nxd = static_cast<int>(x_.size());
  const auto [j, a] = bracket(x_, x);
  const auto [k, b] = bracket(z_, z);
  auto at = [&](int kk, int jj) { return rate_[static_cast<std::size_t>(kk) * nxd + jj]; };
  return (1 - b) * ((1 - a) * at(k, j) + a * at(k, j + 1)) + b * ((1 - a) * at(k + 1, j) + a * at(k + 1, j + 1));
}

}  // namespace grainscale::continuum
