#pragma once
// MUSCL reconstruction (van Leer 1979): a limited linear profile in each cell gives the states just
// left and right of every interior face. Differences are taken in index space (along a layer for
// x-faces, along a column for σ-faces), which is second order on the smoothly mapped terrain grid.
// Limited slopes keep face states inside the range of the neighbouring cell values, so a monotone
// face flux and a small enough step keep c in [0, 1] (Harten's TVD conditions) without clipping.
#include <span>
#include <string>
#include <vector>

#include "continuum/grid.hpp"

namespace grainscale::continuum {

enum class Limiter {
  first_order,  // zero slope: donor cell
  minmod,
  van_leer,     // φ(r) = (r + |r|) / (1 + |r|)
  mc,           // monotonised central
  unlimited     // Fromm's central slope; not bounded, for convergence tests on smooth data only
};

Limiter limiter_from_name(const std::string& name);  // throws InputError listing the names
const std::vector<std::string>& limiter_names();

/// Limited slope (per cell width) from the backward difference a and the forward difference b.
double limited_slope(Limiter limiter, double a, double b);

/// States on both sides of every face. Boundary faces are left at the adjacent cell value.
struct FaceStates {
  std::vector<double> x_left, x_right;  // per x-face: from column f−1 and from column f
  std::vector<double> s_below, s_above; // per σ-face: from layer m−1 and from layer m
};

void reconstruct(const Grid& grid, std::span<const double> c, Limiter limiter, FaceStates& out);

}  // namespace grainscale::continuum
