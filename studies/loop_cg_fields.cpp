#include "studies/loop_cg_fields.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"

namespace grainscale::studies {

namespace {

std::vector<double> read(hid_t file, const std::string& path, const std::string& name, std::vector<hsize_t>& dims) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) throw InputError(path + ": missing dataset '" + name + "'");
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  dims.assign(static_cast<std::size_t>(std::max(H5Sget_simple_extent_ndims(space), 0)), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  hsize_t count = 1;
  for (hsize_t d : dims) count *= d;
  std::vector<double> data(count);
  const herr_t status = H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Sclose(space);
  H5Dclose(set);
  if (status < 0) throw InputError(path + ": cannot read dataset '" + name + "' as numbers");
  return data;
}

double attribute(hid_t file, const std::string& path, const std::string& object, const char* name) {
  const hid_t obj = H5Oopen(file, object.c_str(), H5P_DEFAULT);
  if (obj < 0 || H5Aexists(obj, name) <= 0) {
    if (obj >= 0) H5Oclose(obj);
    throw InputError(path + ": " + object + " has no attribute '" + name + "'");
  }
  const hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  double v = NAN;
  H5Aread(a, H5T_NATIVE_DOUBLE, &v);
  H5Aclose(a);
  H5Oclose(obj);
  return v;
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
    const auto x = read(file, path, "/grid/x", dx), y = read(file, path, "/grid/y", dy), z = read(file, path, "/grid/z", dz);
    const int frames = static_cast<int>(attribute(file, path, "/frames", "count"));
    if (frames < 1) throw InputError(path + ": no frames");
    out << "t_s,x_m,z_m,c\n";
    for (int f = 0; f < frames; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "/frames/%06d", f);
      const double t = attribute(file, path, name, "time");
      std::vector<hsize_t> dc;
      const auto c = read(file, path, std::string(name) + "/chaff_volume_concentration", dc);
      if (dc != std::vector<hsize_t>{z.size(), y.size(), x.size()}) {
        throw InputError(path + ": " + name + "/chaff_volume_concentration is not (nz, ny, nx)");
      }
      for (std::size_t k = 0; k < z.size(); ++k) {
        for (std::size_t i = 0; i < x.size(); ++i) {
          double sum = 0;
          int n = 0;
          for (std::size_t j = 0; j < y.size(); ++j) {
            const double v = c[(k * y.size() + j) * x.size() + i];
            if (std::isfinite(v)) {
              sum += v;
              ++n;
            }
          }
          if (n == 0) continue;  // no particles in this (x, z) cell
          char row[128];
          std::snprintf(row, sizeof row, "%.9g,%.9g,%.9g,%.9g\n", t, x[i], z[k], sum / n);
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
