#pragma once
// Continuum fields derived from the kernel sums (coarsegrain/moments.hpp), per species and for the
// mixture, on the grid. Cells without any mass have undefined velocities, concentrations and
// temperatures; those are NaN (ParaView shows them as blank), densities there are 0.
//
// Definitions (u = j / rho is the mass-weighted velocity, Goldhirsch 2010):
//   volume fraction phi_s, partial density rho_s, number density n_s    straight from the moments
//   chaff concentration by volume   c   = sum_{chaff} phi_s / phi        (phi: mixture)
//                       by number   c_n = sum_{chaff} n_s / n
//                       by mass     c_m = sum_{chaff} rho_s / rho
//   velocity                        u_s = j_s / rho_s (partial), u = j / rho (mixture)
//   granular temperature            T_s = f_s / (3 rho_s), T = f / (3 rho)   (m^2/s^2)
//       f is the fluctuation density of the moments: the mass-weighted mean square deviation of the
//       particle velocities from the cell's velocity, 3 T per unit mass (the trace of the kinetic
//       stress of Goldhirsch 2010). For a window or phase average it is taken about the averaged
//       velocity, so it includes the snapshot-to-snapshot fluctuations (as does the time-averaged
//       kinetic stress of Weinhart et al. 2013).
//   velocity gradient               L_ab = d u_a / d x_b of the mixture velocity, by central
//       differences between neighbouring cells (one-sided at the grid's edge or next to an empty
//       cell, NaN with no occupied neighbour); zero along averaged axes.
//   shear rate                      gamma_dot = sqrt(2 D':D'), D = (L + L^T)/2, D' = D - tr(D)/3 I.
//       Simple shear u_x = G z gives G; rigid translation and rotation give 0; isotropic dilation
//       gives 0 (it is not shear).
//   segregation flux                F = c (u_chaff - u), u_chaff = sum_{chaff} j_s / sum_{chaff} rho_s
//       (0 where there is no chaff; the flux of chaff volume fraction relative to the bulk, per unit
//       bulk volume fraction: the c (u_c - u) of segregation models, e.g. Gray 2018).
//   free-surface height, per column (x, and y on a 3-D grid; dimension >= 2 only): the highest z at
//       which the mixture volume fraction equals `surface_fraction` times the column's bulk value
//       (the column's largest volume fraction, or `bulk_volume_fraction` if set), found downwards
//       from the top and linearly interpolated between cell centres; NaN for an empty column. If the
//       top cell itself exceeds the threshold the surface is reported at the top of the grid.
#include <array>
#include <string>
#include <vector>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/grid.hpp"
#include "coarsegrain/moments.hpp"

namespace grainscale::cg {

struct SpeciesFields {
  std::vector<double> density, volume_fraction, number_density, temperature;
  std::vector<dem::Vec3> velocity;
};

struct FieldOptions {
  double surface_fraction = 0.5;
  double bulk_volume_fraction = 0;  // 0: each column's largest volume fraction
};

struct Fields {
  Grid grid;
  double time = 0;     // mean time of the snapshots averaged
  int snapshots = 0;   // how many
  std::vector<std::string> species_names;
  std::vector<SpeciesFields> species;
  SpeciesFields mixture;
  std::vector<double> chaff_volume_concentration, chaff_number_concentration, chaff_mass_concentration;
  std::vector<std::array<double, 9>> velocity_gradient;  // row-major L_ab = d u_a / d x_b
  std::vector<double> shear_rate;
  std::vector<dem::Vec3> chaff_velocity, segregation_flux;
  std::vector<double> surface_height;  // per column: index i + nx j; empty for a 1-D grid
};

Fields derive_fields(const Moments& moments, const Grid& grid, const SpeciesTable& species, const FieldOptions& options = {});

/// sqrt(2 D':D') for a velocity gradient L (row-major, L_ab = d u_a / d x_b).
double shear_rate(const std::array<double, 9>& L);

}  // namespace grainscale::cg
