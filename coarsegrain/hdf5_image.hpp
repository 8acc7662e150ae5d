#pragma once
// A small HDF5 writer for the field files: the file is built in memory (HDF5 core driver, no
// backing store) and handed back as bytes, which the caller writes with write_file_atomically
// (tmp + fsync + rename), the approach of dem/snapshot.cpp: HDF5 1.10 cannot recover from an I/O
// error while closing a file, so disk errors must surface in plain POSIX writes instead.
// Object time stamps are off, so the same fields give byte-identical files.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

namespace grainscale::cg {

class Hdf5Image {
 public:
  Hdf5Image();
  ~Hdf5Image();
  Hdf5Image(const Hdf5Image&) = delete;
  Hdf5Image& operator=(const Hdf5Image&) = delete;

  /// Create group `path` (absolute, e.g. "/frames/000001"); its parent must exist.
  void group(const std::string& path);
  /// float64 dataset at `path` with shape `dims` (C order; data.size() must match).
  void dataset(const std::string& path, const std::vector<hsize_t>& dims, const std::vector<double>& data);
  /// Attributes on the object at `path` ("/" for the root).
  void attribute(const std::string& path, const std::string& name, double value);
  void attribute(const std::string& path, const std::string& name, std::int32_t value);
  void attribute(const std::string& path, const std::string& name, const std::vector<double>& values);
  void attribute(const std::string& path, const std::string& name, const std::vector<std::int32_t>& values);
  void attribute(const std::string& path, const std::string& name, const std::string& value);
  void attribute(const std::string& path, const std::string& name, const std::vector<std::string>& values);

  /// The finished file's bytes. The image is closed afterwards; no further writes.
  std::string finish();

 private:
  hid_t file_ = -1, gcpl_ = -1, dcpl_ = -1;
};

}  // namespace grainscale::cg
