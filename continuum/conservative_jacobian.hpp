#pragma once
// Band Jacobian ∂(dc/dt)/∂c by grouped difference quotients of the *face fluxes*, assembled face by
// face: a flux derivative g = ∂F/∂c_j enters row L (cell below/left of the face) as −g/A_L and row R
// as +g/A_R. Every column then has Σ_i A_i J_ij = 0 to round-off, which is what lets BDF keep the
// total chaff to round-off (cvode_integrator.cpp). Differencing dc/dt itself, as CVODE's built-in
// band Jacobian does, leaves column sums of order √ε·|J| and a slow drift of the total (~1e-10).
//
// Grouping (Curtis, Powell & Reid 1974): a face between cells L and R = L + {1, nz} depends only on
// cells within the band half-width b of L, so perturbing every (2b+1)-th cell at once leaves each
// face with a single perturbed cell in its window [L − b, L + b]: 2b + 1 flux evaluations per Jacobian.
#include <functional>
#include <span>

#include "continuum/model.hpp"

namespace grainscale::continuum {

/// Calls add(row, column, value) for every entry inside the band |row − column| ≤ b.
void conservative_band_jacobian(const Model& model, double t, std::span<const double> c, int b,
                                const std::function<void(std::size_t, std::size_t, double)>& add,
                                TermPart part = TermPart::all);

/// The same before the division by the cell area: add(row, column, ∂(−Σ_faces F of row)/∂c_column)
/// (the moving-surface state, model.cpp, scales it by its own areas).
void conservative_flux_jacobian(const Model& model, double t, std::span<const double> c, int b, TermPart part,
                                const std::function<void(std::size_t, std::size_t, double)>& add);

}  // namespace grainscale::continuum
