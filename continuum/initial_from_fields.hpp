#pragma once
// The initial chaff field from a coarse-grained DEM frame (a `grainscale cg` fields.h5,
// docs/coarsegrain_layout.md): `initial: {type: file, file: fields.h5, frame: 0}`
// (docs/continuum.md). A model fitted to a DEM run then starts from the run's own poured state,
// not from an idealised one, so what the fit and `grainscale loop` see is the evolution alone.
//
// Mapping: c and the solid fraction φ averaged over y (cg_section.hpp); a model cell (column i,
// layer k, height σ_k h_i) takes c from the nearest coarse-grained column and, in it, the nearest
// cell that is bed (φ ≥ min_solid_fraction); a column without bed cells takes the nearest column
// that has some. c is clamped to [0, 1].
#include <string>
#include <vector>

#include "continuum/grid.hpp"

namespace grainscale::continuum {

/// InputError naming the file for a file that is not a cg field file, a frame out of range
/// (negative counts from the end) or a frame without any bed cell.
std::vector<double> initial_from_cg_frame(const std::string& file, int frame, double min_solid_fraction, const Grid& grid);

}  // namespace grainscale::continuum
