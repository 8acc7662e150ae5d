#include "continuum/initial_from_fields.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "dem/hdf5_numbers.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

namespace {

int int_attribute(hid_t file, const char* object, const char* name) {
  const hid_t obj = H5Oopen(file, object, H5P_DEFAULT);
  if (obj < 0) return 0;
  int v = 0;
  if (H5Aexists(obj, name) > 0) {
    const hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_INT, &v);
    H5Aclose(a);
  }
  H5Oclose(obj);
  return v;
}

/// One frame's c and φ, averaged over y where finite: [nz][nx], NaN where no cell holds particles.
struct Frame {
  std::vector<double> x, z, c, phi;
  double c_at(std::size_t k, std::size_t j) const { return c[k * x.size() + j]; }
  double phi_at(std::size_t k, std::size_t j) const { return phi[k * x.size() + j]; }
};

Frame read_frame(const std::string& path, int frame) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw InputError(path + ": initial.file: cannot open as HDF5");
  Frame f;
  try {
    if (H5Aexists(file, "cg_layout_version") <= 0) throw InputError(path + ": initial.file: not a grainscale cg field file");
    if (int_attribute(file, "/grid", "dimension") != 2) throw InputError(path + ": initial.file: needs a 2-D (x, z) coarse-grained grid");
    const int count = int_attribute(file, "/frames", "count");
    const int n = frame < 0 ? frame + count : frame;
    if (n < 0 || n >= count) {
      throw InputError(path + ": initial.frame = " + std::to_string(frame) + ": the file has frames 0 to " + std::to_string(count - 1));
    }
    char name[32];
    std::snprintf(name, sizeof name, "/frames/%06d/", n);
    std::vector<hsize_t> dx, dy, dz, dc, dp;
    f.x = dem::read_hdf5_doubles(file, path, "/grid/x", dx);
    const std::vector<double> y = dem::read_hdf5_doubles(file, path, "/grid/y", dy);
    f.z = dem::read_hdf5_doubles(file, path, "/grid/z", dz);
    const std::vector<double> c = dem::read_hdf5_doubles(file, path, std::string(name) + "chaff_volume_concentration", dc);
    const std::vector<double> phi = dem::read_hdf5_doubles(file, path, std::string(name) + "mixture/volume_fraction", dp);
    const std::size_t nx = f.x.size(), ny = y.size(), nz = f.z.size();
    if (dc != std::vector<hsize_t>{nz, ny, nx} || dp != dc) {
      throw InputError(path + ": initial.file: frame " + std::to_string(n) + " does not match its grid");
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    f.c.assign(nz * nx, nan);
    f.phi.assign(nz * nx, nan);
    for (std::size_t k = 0; k < nz; ++k)
      for (std::size_t j = 0; j < nx; ++j) {
        double sc = 0, sp = 0;
        int m = 0;
        for (std::size_t l = 0; l < ny; ++l) {
          const std::size_t at = (k * ny + l) * nx + j;
          if (!std::isfinite(c[at]) || !std::isfinite(phi[at])) continue;
          sc += c[at], sp += phi[at], ++m;
        }
        if (m > 0) f.c[k * nx + j] = sc / m, f.phi[k * nx + j] = sp / m;
      }
    H5Fclose(file);
  } catch (...) {
    H5Fclose(file);
    throw;
  }
  return f;
}

}  // namespace

std::vector<double> initial_from_cg_frame(const std::string& path, int frame, double min_solid_fraction, const Grid& g) {
  const Frame f = read_frame(path, frame);
  const std::size_t nx = f.x.size(), nz = f.z.size();
  auto is_bed = [&](std::size_t k, std::size_t j) { return std::isfinite(f.c_at(k, j)) && f.phi_at(k, j) >= min_solid_fraction; };
  std::vector<bool> has_bed(nx, false);
  for (std::size_t j = 0; j < nx; ++j)
    for (std::size_t k = 0; k < nz; ++k) has_bed[j] = has_bed[j] || is_bed(k, j);
  if (std::none_of(has_bed.begin(), has_bed.end(), [](bool b) { return b; })) {
    throw InputError(path + ": initial.frame = " + std::to_string(frame) + ": no cell with solid fraction >= " +
                     std::to_string(min_solid_fraction) + " (initial.min_solid_fraction)");
  }
  std::vector<double> out(g.cells(), 0.0);
  for (int i = 0; i < g.nx(); ++i) {
    // The nearest column with bed cells (ties: the lower x).
    std::size_t best = nx;
    for (std::size_t j = 0; j < nx; ++j) {
      if (has_bed[j] && (best == nx || std::abs(f.x[j] - g.x_centre(i)) < std::abs(f.x[best] - g.x_centre(i)))) best = j;
    }
    for (int k = 0; k < g.nz(); ++k) {
      const double z = g.z_centre(i, k);
      std::size_t kk = nz;
      for (std::size_t l = 0; l < nz; ++l) {
        if (is_bed(l, best) && (kk == nz || std::abs(f.z[l] - z) < std::abs(f.z[kk] - z))) kk = l;
      }
      out[g.index(i, k)] = std::clamp(f.c_at(kk, best), 0.0, 1.0);
    }
  }
  return out;
}

}  // namespace grainscale::continuum
