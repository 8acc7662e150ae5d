#pragma once
// Coarse-graining kernels and their cell-integrated weights.
//
// A particle's mass m at x_p contributes m * W(x - x_p) to the density (Goldhirsch 2010;
// Weinhart et al. 2012). Point-sampling W at cell centres (as MercuryDPM does) conserves mass
// only approximately (1e-2 to 1e-3 next to walls). Here the weight of a cell is the integral of W over
// the cell, so that sum over cells of (density x cell volume) = sum of m exactly, up to rounding.
//
// Kernels are products of one-dimensional kernels, one per resolved axis. That keeps every cell
// integral a product of 1-D integrals in closed form:
//
//   gaussian: W1(s) = exp(-s^2 / 2w^2) / (sqrt(2 pi) w), truncated at |s| = 3w and renormalised
//             (its 3-D product is the isotropic Gaussian inside the cube |s_i| < 3w);
//             cell integral by erf.
//   lucy:     W1(s) = 5/(4c) (1 + 3|s|/c) (1 - |s|/c)^3 for |s| < c (Lucy 1977; the 1-D form used by
//             Weinhart et al. 2012), cell integral by its polynomial antiderivative
//             G(t) = t - 2t^3 + 2t^4 - 3t^5/5, t = |s|/c. The 3-D kernel is the product of 1-D Lucy
//             kernels, not the radial 3-D Lucy kernel.
//
// `width` w is the standard deviation of W1 for both kernels, so both smooth alike: the Gaussian is
// cut off at 3w, Lucy at c = sqrt(10.5) w (the variance of W1 is c^2 / 10.5).
//
// Boundaries (Weinhart et al. 2012, "From discrete particles to continuum fields near a boundary"):
// the part of a particle's kernel beyond a wall of the box is either reflected back into the box
// (image particle at 2 lo - x_p, resp. 2 hi - x_p: a uniform bed then stays uniform up to the wall),
// or the weights inside are simply rescaled to sum to one ("renormalise"). Either way the 1-D weights
// are finally divided by their sum, which makes each particle's weights sum to one to rounding even
// when a kernel is wider than the box (where a single reflection would not be enough).
#include <vector>

#include "coarsegrain/grid.hpp"

namespace grainscale::cg {

enum class KernelType { gaussian, lucy };
enum class Boundary { reflect, renormalise };

const char* name(KernelType t);
const char* name(Boundary b);

struct Kernel {
  KernelType type = KernelType::gaussian;
  double width = 0;  // standard deviation of the 1-D kernel, m
  Boundary boundary = Boundary::reflect;

  /// Half-width of the kernel's support, m (3w for the Gaussian, sqrt(10.5) w for Lucy).
  double cutoff() const;
  /// Integral of W1 from -infinity to s (s in m): 0 below -cutoff, 1 above +cutoff.
  double cdf(double s) const;
};

/// The weights of one particle along one axis: cells first .. first + weight.size() - 1 of that axis.
struct AxisWeights {
  int first = 0;
  std::vector<double> weight;
};

/// Cell-integrated, boundary-treated, normalised weights of a particle at coordinate `x` (inside
/// [grid.lower(axis), grid.upper(axis)]) along `axis`. On an averaged axis: one cell, weight 1.
void axis_weights(const Kernel& kernel, const Grid& grid, int axis, double x, AxisWeights& out);

/// Kernel width in metres from a width in true particle diameters: the snapshot's radii are scaled
/// by `scale_factor`, so the true diameter is 2 r / scale_factor and a 1x and a 2x run coarse-grained
/// with the same `width_diameters` are compared at the same physical resolution.
double kernel_width_m(double width_diameters, double true_diameter_m);

}  // namespace grainscale::cg
