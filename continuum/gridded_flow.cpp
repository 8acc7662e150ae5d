#include "continuum/gridded_flow.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "dem/hdf5_numbers.hpp"
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
  std::vector<double> data = dem::read_hdf5_doubles(file, path, name, dims);
  for (double v : data) {
    if (!std::isfinite(v)) throw InputError(path + ": dataset '" + name + "' holds a NaN or infinity");
  }
  return data;
}

}  // namespace

namespace {

/// Attribute `name` of `obj` as an int, or `fallback` when absent.
int int_attribute(hid_t obj, const char* name, int fallback) {
  if (H5Aexists(obj, name) <= 0) return fallback;
  const hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  int v = fallback;
  H5Aread(a, H5T_NATIVE_INT, &v);
  H5Aclose(a);
  return v;
}

/// The coarse-graining stage's field file (docs/coarsegrain_layout.md, cg_layout_version 1) on a
/// 2-D (x, z) grid: u = x-component of /frames/NNNNNN/mixture/velocity [nz][1][nx][3], γ̇ =
/// shear_rate [nz][1][nx], h = surface_height [1][nx]. Columns the bed does not reach (h = 0 or
/// NaN) are dropped; below a column's surface every value must be finite; above it (no grain) u and
/// γ̇ are irrelevant and set to 0.
void read_cg_fields(hid_t file, const std::string& path, int frame, double temperature_diameter, bool volume_flux,
                    std::vector<double>& x, std::vector<double>& z, std::vector<double>& u, std::vector<double>& rate,
                    std::vector<double>& h) {
  const hid_t grid = H5Gopen2(file, "/grid", H5P_DEFAULT);
  if (grid < 0) throw InputError(path + ": coarse-grained field file without '/grid'");
  const int dimension = int_attribute(grid, "dimension", 0);
  H5Gclose(grid);
  if (dimension != 2) throw InputError(path + ": the continuum model needs a 2-D (x, z) coarse-grained grid, this one is " + std::to_string(dimension) + "-D");
  const hid_t frames = H5Gopen2(file, "/frames", H5P_DEFAULT);
  const int count = frames >= 0 ? int_attribute(frames, "count", 0) : 0;
  if (frames >= 0) H5Gclose(frames);
  if (count <= 0) throw InputError(path + ": no frames in '/frames'");
  if (frame < 0) frame += count;
  if (frame < 0 || frame >= count) {
    throw InputError(path + ": frame " + std::to_string(frame) + " requested, the file has frames 0 to " + std::to_string(count - 1));
  }
  char name[32];
  std::snprintf(name, sizeof name, "/frames/%06d/", frame);
  const std::string f = name;
  std::vector<hsize_t> dx, dz, dv, dr, dh;
  std::vector<double> xs = read_dataset(file, path, "/grid/x", dx);
  z = read_dataset(file, path, "/grid/z", dz);
  // NaN is allowed in the raw fields (empty cells); filtered below.
  auto read_raw = [&](const std::string& n, std::vector<hsize_t>& dims) {
    return dem::read_hdf5_doubles(file, path, n, dims);
  };
  const std::vector<double> vel = read_raw(f + "mixture/velocity", dv);
  const bool by_temperature = temperature_diameter > 0;
  const std::vector<double> gam = read_raw(f + (by_temperature ? "mixture/temperature" : "shear_rate"), dr);
  const std::vector<double> hs = read_raw(f + "surface_height", dh);
  std::vector<hsize_t> dp;
  const std::vector<double> phi = volume_flux ? read_raw(f + "mixture/volume_fraction", dp) : std::vector<double>{};
  if (volume_flux && dp != std::vector<hsize_t>{z.size(), 1, xs.size()}) {
    throw InputError(path + ": frame " + std::to_string(frame) + ": mixture/volume_fraction does not match the 2-D grid");
  }
  const std::size_t nx = xs.size(), nz = z.size();
  if (dv != std::vector<hsize_t>{nz, 1, nx, 3} || dr != std::vector<hsize_t>{nz, 1, nx} || dh != std::vector<hsize_t>{1, nx}) {
    throw InputError(path + ": frame " + std::to_string(frame) + ": fields do not match the 2-D grid (" +
                     std::to_string(nx) + " x " + std::to_string(nz) + ")");
  }
  std::vector<std::size_t> keep;
  for (std::size_t j = 0; j < nx; ++j) {
    if (std::isfinite(hs[j]) && hs[j] > 0) keep.push_back(j);
  }
  if (keep.size() < 2) throw InputError(path + ": frame " + std::to_string(frame) + ": fewer than two columns hold grain");
  x.clear();
  h.clear();
  u.assign(nz * keep.size(), 0.0);
  rate.assign(nz * keep.size(), 0.0);
  for (std::size_t c = 0; c < keep.size(); ++c) {
    const std::size_t j = keep[c];
    x.push_back(xs[j]);
    h.push_back(hs[j]);
    // With volume_flux: u φ / φ̄ (φ̄ the column's mean below its surface), so that ψ carries the solids'
    // volume flux, not the dilute surface cells' fast, nearly massless flow.
    double phi_mean = 1;
    if (volume_flux) {
      double sum = 0;
      int cells = 0;
      for (std::size_t k = 0; k < nz; ++k) {
        if (z[k] > hs[j] || !std::isfinite(phi[k * nx + j])) continue;
        sum += phi[k * nx + j];
        ++cells;
      }
      if (!(sum > 0)) throw InputError(path + ": frame " + std::to_string(frame) + ": no solid below the surface at x = " + std::to_string(xs[j]) + " m");
      phi_mean = sum / cells;
    }
    for (std::size_t k = 0; k < nz; ++k) {
      const double uk = vel[(k * nx + j) * 3], gk = gam[k * nx + j];
      if (z[k] > hs[j]) continue;  // above the surface: no grain
      if (!std::isfinite(uk) || !std::isfinite(gk)) {
        throw InputError(path + ": frame " + std::to_string(frame) + ": NaN velocity, shear rate or temperature below the surface at x = " +
                         std::to_string(xs[j]) + " m, z = " + std::to_string(z[k]) + " m");
      }
      u[k * keep.size() + c] = volume_flux ? uk * (std::isfinite(phi[k * nx + j]) ? phi[k * nx + j] : 0.0) / phi_mean : uk;
      rate[k * keep.size() + c] = by_temperature ? std::sqrt(std::max(gk, 0.0)) / temperature_diameter : std::max(gk, 0.0);
    }
  }
}

}  // namespace

GriddedFlow GriddedFlow::load(const std::string& path, double length, int frame, double temperature_diameter, bool volume_flux) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported as InputError below
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw InputError(path + ": cannot open as HDF5");
  try {
    std::vector<double> x, z, u, r, h;
    if (H5Aexists(file, "cg_layout_version") > 0) {
      read_cg_fields(file, path, frame, temperature_diameter, volume_flux, x, z, u, r, h);
    } else {
      if (temperature_diameter > 0) throw InputError(path + ": mobility from the temperature needs a coarse-graining field file (`grainscale cg`)");
      std::vector<hsize_t> dx, dz, du, dr, dh;
      x = read_dataset(file, path, "/x", dx);
      z = read_dataset(file, path, "/z", dz);
      u = read_dataset(file, path, "/u", du);
      r = read_dataset(file, path, "/shear_rate", dr);
      h = read_dataset(file, path, "/surface_height", dh);
      const std::vector<hsize_t> field{z.size(), x.size()};
      if (du != field || dr != field || h.size() != x.size()) {
        throw InputError(path + ": /u and /shear_rate must be [nz][nx] and /surface_height [nx] for /x [nx], /z [nz]");
      }
    }
    H5Fclose(file);
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

double GriddedFlow::surface_integral(double x) const {
  // Constant h_0 on [0, x_0], trapezoids between columns, constant h_last beyond.
  if (x <= x_.front()) return h_.front() * x;
  double area = h_.front() * x_.front();
  for (std::size_t j = 0; j + 1 < x_.size(); ++j) {
    if (x <= x_[j + 1]) {
      const double hx = h_[j] + (h_[j + 1] - h_[j]) * (x - x_[j]) / (x_[j + 1] - x_[j]);
      return area + 0.5 * (h_[j] + hx) * (x - x_[j]);
    }
    area += 0.5 * (h_[j] + h_[j + 1]) * (x_[j + 1] - x_[j]);
  }
  return area + h_.back() * (x - x_.back());
}

GriddedFlow GriddedFlow::with_surface_scaled(double factor) const {
  std::vector<double> h = h_;
  for (double& v : h) v *= factor;
  return GriddedFlow(length_, x_, z_, u_, rate_, h);
}

std::vector<std::pair<int, double>> GriddedFlow::phase_frames(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw InputError(path + ": cannot open as HDF5");
  std::vector<std::pair<int, double>> out;
  const hid_t frames = H5Gopen2(file, "/frames", H5P_DEFAULT);
  const int count = frames >= 0 ? int_attribute(frames, "count", 0) : 0;
  auto double_attribute = [](hid_t obj, const char* name) {
    double v = std::numeric_limits<double>::quiet_NaN();
    if (H5Aexists(obj, name) > 0) {
      const hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
      H5Aread(a, H5T_NATIVE_DOUBLE, &v);
      H5Aclose(a);
    }
    return v;
  };
  for (int n = 0; n < count; ++n) {
    char name[16];
    std::snprintf(name, sizeof name, "%06d", n);
    const hid_t fr = H5Gopen2(frames, name, H5P_DEFAULT);
    if (fr < 0) continue;
    const double lo = double_attribute(fr, "phase_lo"), hi = double_attribute(fr, "phase_hi");
    const int snapshots = int_attribute(fr, "snapshots", 1);
    H5Gclose(fr);
    if (std::isfinite(lo) && std::isfinite(hi) && snapshots > 0) out.emplace_back(n, 0.5 * (lo + hi));
  }
  if (frames >= 0) H5Gclose(frames);
  H5Fclose(file);
  return out;
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
