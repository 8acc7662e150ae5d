#include "dem/hdf5_numbers.hpp"

#include <algorithm>
#include <cmath>

#include "dem/input_error.hpp"

namespace grainscale::dem {

std::vector<double> read_hdf5_doubles(hid_t file, const std::string& path, const std::string& name,
                                      std::vector<hsize_t>& dims) {
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

std::vector<double> read_hdf5_attribute(hid_t file, const std::string& path, const std::string& object,
                                        const char* name, std::size_t n) {
  const hid_t obj = H5Oopen(file, object.c_str(), H5P_DEFAULT);
  if (obj < 0 || H5Aexists(obj, name) <= 0) {
    if (obj >= 0) H5Oclose(obj);
    throw InputError(path + ": " + object + " has no attribute '" + name + "'");
  }
  const hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  std::vector<double> v(n, NAN);
  H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
  H5Aclose(a);
  H5Oclose(obj);
  return v;
}

}  // namespace grainscale::dem
