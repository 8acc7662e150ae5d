#pragma once
// One frame of a `grainscale cg` field file (docs/coarsegrain_layout.md) seen as an (x, z) section:
// the chaff volume concentration c and the solid fraction φ averaged over y where the cells hold
// particles. What the continuum model and the loop take from a DEM run's fields: its initial state
// (initial_from_fields.hpp) and its measured c (studies/loop_cg_fields.hpp).
#include <string>
#include <vector>

namespace grainscale::continuum {

struct CgSection {
  double time = 0;                 // s, the frame's mean snapshot time
  std::vector<double> x, z;        // cell centres [m]
  std::vector<double> c, phi;      // [nz][nx]; NaN where no cell at (x, z) holds particles
  double c_at(std::size_t k, std::size_t j) const { return c[k * x.size() + j]; }
  double phi_at(std::size_t k, std::size_t j) const { return phi[k * x.size() + j]; }
};

/// Frames in the file. InputError naming the file if it is not a cg field file.
int cg_frame_count(const std::string& file);

/// Frame `frame` (negative counts from the end). InputError naming the file for a file that is not
/// a cg field file, a frame out of range or datasets that do not match the grid.
CgSection read_cg_section(const std::string& file, int frame);

}  // namespace grainscale::continuum
