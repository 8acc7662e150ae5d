#pragma once
// Gridded-flow HDF5 files for the continuum fuzz targets, written with the HDF5 library so that they
// are valid files: libhdf5 1.10 is not robust against corrupt files (README.md), so these targets
// fuzz what grainscale checks (shapes, values, frames) rather than the HDF5 format itself. Layouts:
// docs/continuum.md ("Field input": /x, /z, /u, /shear_rate, /surface_height) and the coarse-grained
// field file (docs/coarsegrain_layout.md: /grid, /frames/NNNNNN/...).
#include <hdf5.h>

#include <cstdio>
#include <string>
#include <vector>

namespace grainscale::fuzz {

/// Write a float64 dataset `name` of shape `dims` (intermediate groups created); false on failure.
inline bool write_h5_dataset(hid_t file, const std::string& name, const std::vector<hsize_t>& dims,
                             const std::vector<double>& values) {
  hsize_t n = 1;
  for (hsize_t d : dims) n *= d;
  if (n != values.size()) return false;
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t set = space < 0 ? -1 : H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  bool ok = set >= 0 && (n == 0 || H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) >= 0);
  if (set >= 0) H5Dclose(set);
  if (space >= 0) H5Sclose(space);
  H5Pclose(lcpl);
  return ok;
}

/// Write an int32 attribute on the object at `object` (a group path), creating the group if needed.
inline bool write_h5_int_attribute(hid_t file, const std::string& object, const char* name, int value) {
  hid_t obj = object == "/" ? H5Gopen2(file, "/", H5P_DEFAULT) : -1;
  if (obj < 0 && H5Lexists(file, object.c_str(), H5P_DEFAULT) > 0) obj = H5Oopen(file, object.c_str(), H5P_DEFAULT);
  if (obj < 0) obj = H5Gcreate2(file, object.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (obj < 0) return false;
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(obj, name, H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT);
  const bool ok = a >= 0 && H5Awrite(a, H5T_NATIVE_INT, &value) >= 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  H5Oclose(obj);
  return ok;
}

/// A small valid flow in the plain layout: 4 columns in (0, 0.8) m, 3 levels, a bed 0.1 m deep.
inline void write_valid_flow_file(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  write_h5_dataset(f, "/x", {4}, {0.1, 0.3, 0.5, 0.7});
  write_h5_dataset(f, "/z", {3}, {0.0, 0.05, 0.1});
  write_h5_dataset(f, "/u", {3, 4}, {0.01, 0.01, 0.01, 0.01, 0, 0, 0, 0, -0.01, -0.01, -0.01, -0.01});
  write_h5_dataset(f, "/shear_rate", {3, 4}, std::vector<double>(12, 0.1));
  write_h5_dataset(f, "/surface_height", {4}, {0.1, 0.1, 0.1, 0.1});
  H5Fclose(f);
}

}  // namespace grainscale::fuzz
