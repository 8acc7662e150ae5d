#pragma once
// The kernel sums from which every field is derived, per species and for the mixture, per cell.
//
// For a cell c of volume V_c and particle weights W_pc (the cell integral of the kernel, summing to one
// over cells for every particle; coarsegrain/kernel.hpp), following Goldhirsch 2010
// and Weinhart et al. 2012 (full references in docs/coarsegrain_layout.md), in cell-integrated form:
//
//   partial density        rho_s = sum_{p in s} m_p W_pc / V_c                      kg/m^3
//   partial volume frac.   phi_s = sum_{p in s} V_p W_pc / V_c                      -
//   number density         n_s   = sum_{p in s} N_p W_pc / V_c                      1/m^3
//   momentum density       j_s   = sum_{p in s} m_p v_p W_pc / V_c                  kg/(m^2 s)
//   fluctuation density    f_s   = sum_{p in s} m_p |v_p - u_s|^2 W_pc / V_c,  u_s = j_s / rho_s   J/m^3 (x2)
//
// N_p is the sphere's share of its body (grain or flake), so n counts bodies. f_s is twice the
// kinetic energy density of the velocity fluctuations, the trace of Goldhirsch's kinetic stress.
// It is summed in a second pass with u_s already known, never as sum m v^2 - rho u^2, which would
// cancel catastrophically in a slowly, rigidly moving bed.
//
// Index `species` (= number of species) holds the mixture: all particles, with f about the mixture
// velocity u = j / rho.
#include <cstddef>
#include <vector>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/grid.hpp"
#include "coarsegrain/kernel.hpp"

namespace grainscale::cg {

struct Moments {
  int species = 0;        // number of species; row `species` is the mixture
  std::size_t cells = 0;  // grid.size()
  /// Number of snapshots summed in (see add and average).
  int snapshots = 0;
  double time = 0;  // sum of the snapshots' times (the mean after average())

  std::vector<double> mass, volume, number, fluctuation;  // [(species + 1) * cells], row s at s * cells
  std::vector<dem::Vec3> momentum;

  /// Mass of particles whose centre lies outside the grid's box (not spread); summed like the fields.
  double excluded_mass = 0;
  std::size_t excluded_count = 0;

  Moments() = default;
  Moments(int n_species, std::size_t n_cells);

  std::size_t at(int s, std::size_t cell) const { return static_cast<std::size_t>(s) * cells + cell; }
  int mixture() const { return species; }

  /// Sum in another set of moments of the same shape (a later snapshot of a window). Densities add;
  /// fluctuations combine with the between-set term rho_a rho_b / (rho_a + rho_b) |u_a - u_b|^2 (Chan,
  /// Golub & LeVeque 1983), so that the combined f is the fluctuation about the combined velocity,
  /// exactly and without cancellation.
  void add(const Moments& other);
  /// Divide the sums by the number of snapshots added: the window average (time: the mean time).
  void average();
};

/// Coarse-grain one particle set onto `grid`: the moments of one snapshot (snapshots = 1).
/// Deterministic: each cell's sums run over particles in a fixed order whatever the thread count.
Moments coarse_grain(const CgParticles& particles, int n_species, const Grid& grid, const Kernel& kernel);

}  // namespace grainscale::cg
