#pragma once
// Every input problem (YAML, STL, CSV, HDF5) is reported as an InputError whose message names the
// file, the line where known, the key and the allowed range. Always on, never an assert.
#include <stdexcept>
#include <string>

namespace grainscale {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace grainscale
