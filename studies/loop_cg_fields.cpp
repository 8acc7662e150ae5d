#include "studies/loop_cg_fields.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "dem/atomic_file.hpp"
#include "dem/hdf5_numbers.hpp"
#include "dem/input_error.hpp"

namespace grainscale::studies {

namespace {

using dem::read_hdf5_doubles;

double attribute(hid_t file, const std::string& path, const std::string& object, const char* name) {
  return dem::read_hdf5_attribute(file, path, object, name)[0];
}

}  // namespace

std::size_t cg_fields_to_csv(const std::string& path, const std::string& csv_path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw InputError(path + ": cannot open as HDF5");
  std::ostringstream out;
  std::size_t rows = 0;
  try {
    if (H5Aexists(file, "cg_layout_version") <= 0) throw InputError(path + ": not a grainscale cg field file (no cg_layout_version)");
    std::vector<hsize_t> dx, dy, dz;
    const auto x = read_hdf5_doubles(file, path, "/grid/x", dx), y = read_hdf5_doubles(file, path, "/grid/y", dy), z = read_hdf5_doubles(file, path, "/grid/z", dz);
    const int frames = static_cast<int>(attribute(file, path, "/frames", "count"));
    if (frames < 1) throw InputError(path + ": no frames");
    out << "t_s,x_m,z_m,c,phi\n";
    for (int f = 0; f < frames; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "/frames/%06d", f);
      const double t = attribute(file, path, name, "time");
      std::vector<hsize_t> dc;
      const auto c = read_hdf5_doubles(file, path, std::string(name) + "/chaff_volume_concentration", dc);
      if (dc != std::vector<hsize_t>{z.size(), y.size(), x.size()}) {
        throw InputError(path + ": " + name + "/chaff_volume_concentration is not (nz, ny, nx)");
      }
      std::vector<hsize_t> dp;
      const auto phi = read_hdf5_doubles(file, path, std::string(name) + "/mixture/volume_fraction", dp);
      if (dp != dc) throw InputError(path + ": " + name + "/mixture/volume_fraction is not (nz, ny, nx)");
      for (std::size_t k = 0; k < z.size(); ++k) {
        for (std::size_t i = 0; i < x.size(); ++i) {
          double sum = 0, solid = 0;
          int n = 0;
          for (std::size_t j = 0; j < y.size(); ++j) {
            const std::size_t at = (k * y.size() + j) * x.size() + i;
            if (std::isfinite(c[at])) {
              sum += c[at];
              solid += phi[at];
              ++n;
            }
          }
          if (n == 0) continue;  // no particles in this (x, z) cell
          char row[160];
          std::snprintf(row, sizeof row, "%.9g,%.9g,%.9g,%.9g,%.9g\n", t, x[i], z[k], sum / n, solid / n);
          out << row;
          ++rows;
        }
      }
    }
    H5Fclose(file);
  } catch (...) {
    H5Fclose(file);
    throw;
  }
  dem::write_file_atomically(csv_path, out.str());
  return rows;
}

}  // namespace grainscale::studies
