#pragma once
// The `grainscale continuum`-style run, read as the algorithm: settings -> model -> integrate
// through the output times (stopping at forcing jumps) -> write HDF5 and CSV atomically.
#include <string>

#include "continuum/settings.hpp"

namespace grainscale::continuum {

struct ContinuumRunSummary {
  std::string h5_file, slices_file, coverage_file;
  double chaff_initial = 0, chaff_final = 0;  // [m²] per unit width
  double c_min = 0, c_max = 0;                // over all outputs
  long steps = 0;
};

/// Throws InputError for bad settings, std::runtime_error for integrator or output failures.
ContinuumRunSummary run_continuum(const ContinuumSettings& settings);

}  // namespace grainscale::continuum
