#pragma once
// Writing small HDF5 files for the tests that read coarse-grained field files
// (docs/coarsegrain_layout.md): a float64 dataset and a scalar int or double attribute.
#include <hdf5.h>

#include <type_traits>
#include <vector>

namespace grainscale::testing {

inline void dataset(hid_t loc, const char* name, const std::vector<hsize_t>& dims, const std::vector<double>& v) {
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t set = H5Dcreate2(loc, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(set);
  H5Sclose(space);
}

template <typename T>
void attribute(hid_t loc, const char* name, T v) {
  static_assert(std::is_same_v<T, int> || std::is_same_v<T, double>);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t type = std::is_same_v<T, int> ? H5T_STD_I32LE : H5T_IEEE_F64LE;
  const hid_t a = H5Acreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, std::is_same_v<T, int> ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE, &v);
  H5Aclose(a);
  H5Sclose(space);
}

}  // namespace grainscale::testing
