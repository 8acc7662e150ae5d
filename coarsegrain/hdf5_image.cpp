#include "coarsegrain/hdf5_image.hpp"

#include <atomic>
#include <stdexcept>

namespace grainscale::cg {

namespace {

/// HDF5 prints its error stack by default; here failures become exceptions instead.
struct Quiet {
  H5E_auto2_t func = nullptr;
  void* data = nullptr;
  Quiet() {
    H5Eget_auto2(H5E_DEFAULT, &func, &data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~Quiet() { H5Eset_auto2(H5E_DEFAULT, func, data); }
};

hid_t ok(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("HDF5 failed " + what);
  return id;
}

/// Closes an hid_t at scope exit.
struct Owned {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Owned() {
    if (id >= 0) close(id);
  }
};

Owned open_object(hid_t file, const std::string& path) {
  return {ok(H5Oopen(file, path.c_str(), H5P_DEFAULT), "opening " + path), H5Oclose};
}

void write_attribute(hid_t file, const std::string& path, const std::string& name, hid_t type, hid_t mem_type,
                     const std::vector<hsize_t>& dims, const void* data) {
  const Quiet quiet;
  const Owned obj = open_object(file, path);
  const Owned space{ok(dims.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                       "creating a dataspace"),
                    H5Sclose};
  const std::string what = "writing attribute '" + name + "' on " + path;
  const Owned a{ok(H5Acreate2(obj.id, name.c_str(), type, space.id, H5P_DEFAULT, H5P_DEFAULT), what), H5Aclose};
  if (H5Sget_simple_extent_npoints(space.id) > 0 && H5Awrite(a.id, mem_type, data) < 0) throw std::runtime_error("HDF5 failed " + what);
}

Owned string_type() {
  Owned t{ok(H5Tcopy(H5T_C_S1), "creating the string type"), H5Tclose};
  H5Tset_size(t.id, H5T_VARIABLE);
  H5Tset_cset(t.id, H5T_CSET_UTF8);
  return t;
}

}  // namespace

Hdf5Image::Hdf5Image() {
  const Quiet quiet;
  const Owned fcpl{ok(H5Pcreate(H5P_FILE_CREATE), "creating file properties"), H5Pclose};
  H5Pset_obj_track_times(fcpl.id, false);
  const Owned fapl{ok(H5Pcreate(H5P_FILE_ACCESS), "creating file access properties"), H5Pclose};
  ok(H5Pset_fapl_core(fapl.id, 1 << 20, false), "selecting the in-memory driver");
  static std::atomic<unsigned long> serial{0};
  const std::string name = "grainscale_cg_image_" + std::to_string(serial++);
  file_ = ok(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, fcpl.id, fapl.id), "creating the in-memory file");
  gcpl_ = ok(H5Pcreate(H5P_GROUP_CREATE), "creating group properties");
  H5Pset_obj_track_times(gcpl_, false);
  dcpl_ = ok(H5Pcreate(H5P_DATASET_CREATE), "creating dataset properties");
  H5Pset_obj_track_times(dcpl_, false);
}

Hdf5Image::~Hdf5Image() {
  if (dcpl_ >= 0) H5Pclose(dcpl_);
  if (gcpl_ >= 0) H5Pclose(gcpl_);
  if (file_ >= 0) H5Fclose(file_);
}

void Hdf5Image::group(const std::string& path) {
  const Quiet quiet;
  H5Gclose(ok(H5Gcreate2(file_, path.c_str(), H5P_DEFAULT, gcpl_, H5P_DEFAULT), "creating group " + path));
}

void Hdf5Image::dataset(const std::string& path, const std::vector<hsize_t>& dims, const std::vector<double>& data) {
  const Quiet quiet;
  hsize_t n = 1;
  for (const hsize_t d : dims) n *= d;
  if (n != data.size()) throw std::logic_error("dataset " + path + ": shape does not match the data");
  const Owned space{ok(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), "creating a dataspace"), H5Sclose};
  const Owned d{ok(H5Dcreate2(file_, path.c_str(), H5T_IEEE_F64LE, space.id, H5P_DEFAULT, dcpl_, H5P_DEFAULT), "creating " + path),
                H5Dclose};
  if (n > 0 && H5Dwrite(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0) {
    throw std::runtime_error("HDF5 failed writing " + path);
  }
}

void Hdf5Image::attribute(const std::string& path, const std::string& name, double value) {
  write_attribute(file_, path, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &value);
}
void Hdf5Image::attribute(const std::string& path, const std::string& name, std::int32_t value) {
  write_attribute(file_, path, name, H5T_STD_I32LE, H5T_NATIVE_INT32, {}, &value);
}
void Hdf5Image::attribute(const std::string& path, const std::string& name, const std::vector<double>& v) {
  write_attribute(file_, path, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {v.size()}, v.data());
}
void Hdf5Image::attribute(const std::string& path, const std::string& name, const std::vector<std::int32_t>& v) {
  write_attribute(file_, path, name, H5T_STD_I32LE, H5T_NATIVE_INT32, {v.size()}, v.data());
}
void Hdf5Image::attribute(const std::string& path, const std::string& name, const std::string& value) {
  const Owned t = string_type();
  const char* p = value.c_str();
  write_attribute(file_, path, name, t.id, t.id, {}, &p);
}
void Hdf5Image::attribute(const std::string& path, const std::string& name, const std::vector<std::string>& values) {
  const Owned t = string_type();
  std::vector<const char*> p;
  for (const auto& s : values) p.push_back(s.c_str());
  write_attribute(file_, path, name, t.id, t.id, {values.size()}, p.data());
}

std::string Hdf5Image::finish() {
  const Quiet quiet;
  if (H5Fflush(file_, H5F_SCOPE_GLOBAL) < 0) throw std::runtime_error("HDF5 failed flushing the in-memory file");
  const ssize_t size = H5Fget_file_image(file_, nullptr, 0);
  if (size < 0) throw std::runtime_error("HDF5 failed getting the file image");
  std::string image(static_cast<std::size_t>(size), '\0');
  if (H5Fget_file_image(file_, image.data(), image.size()) != size) throw std::runtime_error("HDF5 failed getting the file image");
  H5Pclose(dcpl_);
  H5Pclose(gcpl_);
  H5Fclose(file_);
  dcpl_ = gcpl_ = file_ = -1;
  return image;
}

}  // namespace grainscale::cg
