#include "coarsegrain/kernel.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainscale::cg {

namespace {

constexpr double kGaussianCutoff = 3.0;        // in widths
const double kLucyCutoff = std::sqrt(10.5);    // in widths: variance of the 1-D Lucy kernel is c^2 / 10.5

/// Standard normal distribution function.
double phi(double t) { return 0.5 * std::erfc(-t / std::sqrt(2.0)); }

/// Integral of the 1-D Lucy kernel (unit cut-off) from 0 to t, 0 <= t <= 1: (5/4) G(t).
double lucy_half_cdf(double t) { return 1.25 * t * (1.0 + t * t * (-2.0 + t * (2.0 - 0.6 * t))); }

}  // namespace

const char* name(KernelType t) { return t == KernelType::gaussian ? "gaussian" : "lucy"; }
const char* name(Boundary b) { return b == Boundary::reflect ? "reflect" : "renormalise"; }

double Kernel::cutoff() const { return (type == KernelType::gaussian ? kGaussianCutoff : kLucyCutoff) * width; }

double Kernel::cdf(double s) const {
  const double c = cutoff();
  if (s <= -c) return 0.0;
  if (s >= c) return 1.0;
  if (type == KernelType::gaussian) {
    // Truncated normal: (Phi(s/w) - Phi(-3)) / (Phi(3) - Phi(-3)).
    const double lo = phi(-kGaussianCutoff), hi = phi(kGaussianCutoff);
    return (phi(s / width) - lo) / (hi - lo);
  }
  const double t = std::abs(s) / c;
  return s >= 0 ? 0.5 + lucy_half_cdf(t) : 0.5 - lucy_half_cdf(t);
}

void axis_weights(const Kernel& kernel, const Grid& grid, int axis, double x, AxisWeights& out) {
  out.weight.clear();
  if (!grid.resolved(axis)) {
    out.first = 0;
    out.weight.push_back(1.0);
    return;
  }
  const int n = grid.cells[static_cast<std::size_t>(axis)];
  const double lo = grid.lower(axis), hi = grid.upper(axis), h = grid.spacing(axis), c = kernel.cutoff();
  const int first = std::clamp(static_cast<int>(std::floor((x - c - lo) / h)), 0, n - 1);
  const int last = std::clamp(static_cast<int>(std::floor((x + c - lo) / h)), 0, n - 1);
  out.first = first;
  // Images only matter for a particle within one cut-off of a wall; elsewhere they add exact zeros.
  const bool reflect_lo = kernel.boundary == Boundary::reflect && x - lo < c;
  const bool reflect_hi = kernel.boundary == Boundary::reflect && hi - x < c;
  const double image_lo = 2 * lo - x, image_hi = 2 * hi - x;
  double sum = 0;
  // The cdf at each edge is computed once and differenced, so adjacent cells share edge values.
  double f_direct = kernel.cdf(grid.edge(axis, first) - x);
  double f_lo = reflect_lo ? kernel.cdf(grid.edge(axis, first) - image_lo) : 0.0;
  double f_hi = reflect_hi ? kernel.cdf(grid.edge(axis, first) - image_hi) : 0.0;
  for (int i = first; i <= last; ++i) {
    const double b = grid.edge(axis, i + 1);
    const double g_direct = kernel.cdf(b - x);
    double w = g_direct - f_direct;
    f_direct = g_direct;
    if (reflect_lo) {
      const double g_lo = kernel.cdf(b - image_lo);
      w += g_lo - f_lo;
      f_lo = g_lo;
    }
    if (reflect_hi) {
      const double g_hi = kernel.cdf(b - image_hi);
      w += g_hi - f_hi;
      f_hi = g_hi;
    }
    out.weight.push_back(w);
    sum += w;
  }
  if (!(sum > 0)) throw std::logic_error("coarse-graining weights vanish: particle outside the grid");
  for (double& w : out.weight) w /= sum;
}

double kernel_width_m(double width_diameters, double true_diameter_m) { return width_diameters * true_diameter_m; }

}  // namespace grainscale::cg
