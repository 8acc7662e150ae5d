#pragma once
// Coarse-grained fields on disk: one HDF5 file holding every output frame (layout in
// docs/coarsegrain_layout.md, versioned by kFieldLayoutVersion) and an XDMF file beside it that lets
// ParaView open the frames as a time series of cell data on the grid. Both are written atomically.
#include <string>
#include <vector>

#include "coarsegrain/fields.hpp"
#include "coarsegrain/kernel.hpp"

namespace grainscale::cg {

/// Version of the field file layout; increase it with any change that removes, renames or
/// re-interprets something in docs/coarsegrain_layout.md.
inline constexpr int kFieldLayoutVersion = 1;

/// One output frame: the fields plus what they average.
struct FieldFrame {
  Fields fields;
  std::string averaging = "snapshot";  // snapshot | window | phase
  double phase_lo = 0, phase_hi = 0;   // phase bin in cycles (phase frames only)
};

/// Run metadata stored as root attributes.
struct FieldFileInfo {
  Kernel kernel;
  double width_diameters = 0, true_diameter = 0, scale_factor = 1;
  std::string container_wall;
  std::vector<std::string> chaff_species;
  std::vector<std::string> snapshots;  // source files, in order
  double max_mass_error = 0;           // largest relative mass conservation error of any snapshot
};

/// Write `frames` (all on the same grid and species) to `h5_path`. std::runtime_error naming the
/// path if it cannot be written; std::invalid_argument for a species name that cannot be a group name.
void write_field_file(const std::string& h5_path, const std::vector<FieldFrame>& frames, const FieldFileInfo& info);

/// Write the XDMF 2 description of a field file: a temporal collection of 3DCoRectMesh grids with
/// every field as cell data. `h5_reference` is the field file's path relative to the .xmf.
void write_field_xdmf(const std::string& xmf_path, const std::string& h5_reference, const std::vector<FieldFrame>& frames);

}  // namespace grainscale::cg
