#include "continuum/h5_writer.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace grainscale::continuum {

namespace {
void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what + " failed");
}
hid_t check_id(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("HDF5: " + what + " failed");
  return id;
}
}  // namespace

H5Writer::H5Writer(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
  file_ = check_id(H5Fcreate(tmp_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "creating " + tmp_);
}

H5Writer::~H5Writer() {
  if (file_ >= 0) {
    H5Fclose(file_);
    std::remove(tmp_.c_str());
  }
}

void H5Writer::group(const std::string& name) {
  const hid_t g = check_id(H5Gcreate2(file_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "group " + name);
  H5Gclose(g);
}

void H5Writer::dataset(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<double>& data) {
  hsize_t count = 1;
  for (hsize_t d : dims) count *= d;
  if (count != data.size()) throw std::runtime_error("HDF5: dataset " + name + " has the wrong size");
  const hid_t space = check_id(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), "dataspace");
  const hid_t set = H5Dcreate2(file_, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Sclose(space);
  check_id(set, "dataset " + name);
  const herr_t status = H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Dclose(set);
  check(status, "writing " + name);
}

void H5Writer::attribute(const std::string& object, const std::string& name, const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  H5Tset_strpad(type, H5T_STR_NULLTERM);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate_by_name(file_, object.c_str(), name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT,
                                       H5P_DEFAULT);
  H5Sclose(space);
  if (attr < 0) {
    H5Tclose(type);
    throw std::runtime_error("HDF5: attribute " + object + ":" + name);
  }
  const herr_t status = H5Awrite(attr, type, value.c_str());
  H5Aclose(attr);
  H5Tclose(type);
  check(status, "writing attribute " + name);
}

void H5Writer::attribute(const std::string& object, const std::string& name, double value) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate_by_name(file_, object.c_str(), name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                       H5P_DEFAULT, H5P_DEFAULT);
  H5Sclose(space);
  check_id(attr, "attribute " + object + ":" + name);
  const herr_t status = H5Awrite(attr, H5T_NATIVE_DOUBLE, &value);
  H5Aclose(attr);
  check(status, "writing attribute " + name);
}

void H5Writer::attribute(const std::string& object, const std::string& name, long value) {
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate_by_name(file_, object.c_str(), name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT,
                                       H5P_DEFAULT, H5P_DEFAULT);
  H5Sclose(space);
  check_id(attr, "attribute " + object + ":" + name);
  const herr_t status = H5Awrite(attr, H5T_NATIVE_LONG, &value);
  H5Aclose(attr);
  check(status, "writing attribute " + name);
}

void H5Writer::close() {
  check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flushing " + tmp_);
  const herr_t status = H5Fclose(file_);
  file_ = -1;
  if (status < 0) {
    std::remove(tmp_.c_str());
    throw std::runtime_error("HDF5: closing " + tmp_ + " failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp_, path_, ec);
  if (ec) {
    std::remove(tmp_.c_str());
    throw std::runtime_error("cannot rename " + tmp_ + " to " + path_ + ": " + ec.message());
  }
}

}  // namespace grainscale::continuum
