#include "continuum/cg_section.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "dem/hdf5_numbers.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

namespace {

/// The open file, closed on every way out.
struct File {
  hid_t id;
  explicit File(const std::string& path) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (id < 0) throw InputError(path + ": cannot open as HDF5");
    if (H5Aexists(id, "cg_layout_version") <= 0) {
      H5Fclose(id);
      throw InputError(path + ": not a grainscale cg field file (no cg_layout_version)");
    }
  }
  ~File() { H5Fclose(id); }
  File(const File&) = delete;
  File& operator=(const File&) = delete;
};

int count_of(const File& f, const std::string& path) {
  return static_cast<int>(dem::read_hdf5_attribute(f.id, path, "/frames", "count")[0]);
}

}  // namespace

int cg_frame_count(const std::string& path) { return count_of(File(path), path); }

CgSection read_cg_section(const std::string& path, int frame) {
  const File f(path);
  const int count = count_of(f, path);
  const int n = frame < 0 ? frame + count : frame;
  if (n < 0 || n >= count) {
    throw InputError(path + ": frame " + std::to_string(frame) + " requested, the file has frames 0 to " + std::to_string(count - 1));
  }
  char name[32];
  std::snprintf(name, sizeof name, "/frames/%06d", n);
  CgSection s;
  s.time = dem::read_hdf5_attribute(f.id, path, name, "time")[0];
  std::vector<hsize_t> dx, dy, dz, dc, dp;
  s.x = dem::read_hdf5_doubles(f.id, path, "/grid/x", dx);
  const std::vector<double> y = dem::read_hdf5_doubles(f.id, path, "/grid/y", dy);
  s.z = dem::read_hdf5_doubles(f.id, path, "/grid/z", dz);
  const std::vector<double> c = dem::read_hdf5_doubles(f.id, path, std::string(name) + "/chaff_volume_concentration", dc);
  const std::vector<double> phi = dem::read_hdf5_doubles(f.id, path, std::string(name) + "/mixture/volume_fraction", dp);
  const std::size_t nx = s.x.size(), ny = y.size(), nz = s.z.size();
  if (dc != std::vector<hsize_t>{nz, ny, nx}) throw InputError(path + ": " + name + "/chaff_volume_concentration is not (nz, ny, nx)");
  if (dp != dc) throw InputError(path + ": " + name + "/mixture/volume_fraction is not (nz, ny, nx)");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.c.assign(nz * nx, nan);
  s.phi.assign(nz * nx, nan);
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t j = 0; j < nx; ++j) {
      double sc = 0, sp = 0;
      int m = 0;
      for (std::size_t l = 0; l < ny; ++l) {
        const std::size_t at = (k * ny + l) * nx + j;
        if (!std::isfinite(c[at])) continue;  // no particles in this cell
        sc += c[at], sp += phi[at], ++m;
      }
      if (m > 0) s.c[k * nx + j] = sc / m, s.phi[k * nx + j] = sp / m;
    }
  return s;
}

}  // namespace grainscale::continuum
