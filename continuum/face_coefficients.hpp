#pragma once
// Flow quantities on the faces of the terrain-following grid at one time: volume fluxes from ψ at
// the cell corners (so Σ over a cell's faces is zero by construction) and γ̇ at face centres.
//
// Face numbering: x-face (f, k), f = 0..nx, k = 0..nz−1, at x = f dx, stored at f * nz + k;
// σ-face (i, m), i = 0..nx−1, m = 0..nz, the sloping side z = σ_m h(x) of column i, stored at
// i * (nz + 1) + m. Fluxes are positive in +x and upward.
//
// Moving free surface (flow.moving_surface()): the grid passed in has its nodes at h(x_f, t). The
// σ-faces z = σ h(x, t) move, and what crosses a σ-face is the bulk flux *relative to the face*:
//   Q_rel(i, m) = Q(i, m) − σ_m ȧ_i,    ȧ_i = q_i − q_{i+1},   q_f = ψ(x_f, h_f, t),          (F1)
// ȧ_i = d(column area)/dt by the kinematic condition in finite-volume form. Then Σ_faces Q_rel of
// cell (i, k) = −dσ ȧ_i = −dA/dt exactly (discrete geometric conservation law), and Q_rel = 0
// through the surface itself. Advection uses Q_rel; segregation and diffusion are fluxes relative to
// the bulk and need no correction.
#include <cstddef>
#include <vector>

#include "continuum/flow.hpp"
#include "continuum/grid.hpp"

namespace grainscale::continuum {

inline std::size_t x_face(const Grid& g, int f, int k) { return static_cast<std::size_t>(f) * g.nz() + k; }
inline std::size_t s_face(const Grid& g, int i, int m) { return static_cast<std::size_t>(i) * (g.nz() + 1) + m; }
inline std::size_t x_face_count(const Grid& g) { return static_cast<std::size_t>(g.nx() + 1) * g.nz(); }
inline std::size_t s_face_count(const Grid& g) { return static_cast<std::size_t>(g.nx()) * (g.nz() + 1); }

struct FaceCoefficients {
  std::vector<double> volume_flux_x;  // ∫ u dz over the x-face [m²/s]
  std::vector<double> volume_flux_s;  // ∫ (w − u dz_face/dx) dx over the σ-face [m²/s]
  std::vector<double> shear_x;        // γ̇ at x-face centres [1/s]
  std::vector<double> shear_s;        // γ̇ at σ-face centres [1/s]
  std::vector<double> column_area_rate;  // ȧ_i per column [m²/s] (F1); zeros for a fixed surface

  /// Evaluate everything from `flow` at time t.
  void update(const Grid& grid, const Flow& flow, double t);
};

/// Volume flux through one face from ψ at its two end points (the discrete form of ∫ u·n ds = Δψ).
double face_volume_flux(double psi_start, double psi_end);

}  // namespace grainscale::continuum
