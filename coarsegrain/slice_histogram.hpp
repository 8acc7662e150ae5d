#pragma once
// The report's Figure 11 measure: chaff particles per 50 mm slice along the container, as a
// percentage of all chaff particles, plus the chaff concentration of each slice.
//
// Particles are bodies (a chaff flake of four spheres is one particle), counted at their centre of
// mass as the report did. The concentration by volume uses the spheres, each at its own centre, with
// its volume (coarsegrain/cg_particles.hpp), so a flake straddling two slices is shared.
#include <vector>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/slices.hpp"

namespace grainscale::cg {

struct SliceHistogram {
  Slices slices;
  std::vector<double> chaff_bodies, grain_bodies;  // counts per slice
  std::vector<double> chaff_percent;               // 100 x chaff_bodies / all chaff bodies in the slices
  std::vector<double> chaff_number_fraction;       // chaff bodies / all bodies of the slice (NaN if none)
  std::vector<double> chaff_volume_fraction;       // chaff sphere volume / all sphere volume (NaN if none)
  double chaff_total = 0, grain_total = 0;         // bodies inside the slices
  int outside = 0;                                 // bodies whose centre is outside [x_lo, x_hi]
};

SliceHistogram slice_histogram(const CgParticles& particles, const SpeciesTable& species, const Slices& slices);

}  // namespace grainscale::cg
