#pragma once
// Minimal HDF5 writing for the continuum output: groups, double datasets of any rank, and scalar
// attributes. The file is written under `path.tmp` and renamed over `path` by close(), so a reader
// never sees a half-written file (the convention of dem/atomic_file.hpp).
#include <hdf5.h>

#include <string>
#include <vector>

namespace grainscale::continuum {

class H5Writer {
 public:
  explicit H5Writer(std::string path);
  ~H5Writer();  // a writer not closed removes its temporary file
  H5Writer(const H5Writer&) = delete;
  H5Writer& operator=(const H5Writer&) = delete;

  void group(const std::string& name);
  void dataset(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<double>& data);
  void attribute(const std::string& object, const std::string& name, const std::string& value);
  void attribute(const std::string& object, const std::string& name, double value);
  void attribute(const std::string& object, const std::string& name, long value);
  /// Flush, close and rename into place. Throws std::runtime_error on failure.
  void close();

 private:
  std::string path_, tmp_;
  hid_t file_ = -1;
};

}  // namespace grainscale::continuum
