// HDF5 snapshots (dem/snapshot.hpp). Malformed HDF5 also exercises libhdf5 itself, whose own
// robustness against corrupt files is limited (its CVE list); see tests/fuzz/README.md.
#include "dem/input_error.hpp"
#include "dem/snapshot.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed_snapshot.h5");
  try {
    (void)grainscale::dem::read_snapshot(path);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
