#pragma once
// Coarse-grained DEM fields (a `grainscale cg` fields.h5, docs/coarsegrain_layout.md) as measured
// data for `grainscale loop`: every frame's chaff volume concentration, averaged over y where the
// cells hold particles, becomes rows t_s,x_m,z_m,c,phi of a CSV (phi: the solid volume fraction there) (the layout fit_observations.hpp reads),
// so the same nearest-cell mapping and inverse-variance combination apply to DEM and to measurements.
#include <string>

namespace grainscale::studies {

/// Write the CSV; returns the number of rows with a value. InputError naming the file for anything
/// missing (not a cg field file, no frames, a dataset of the wrong shape).
std::size_t cg_fields_to_csv(const std::string& h5_path, const std::string& csv_path);

}  // namespace grainscale::studies
