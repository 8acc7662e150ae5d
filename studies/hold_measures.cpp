#include "studies/hold_measures.hpp"

#include <algorithm>

namespace grainscale::studies {

std::vector<double> surface_concentration(const continuum::Grid& g, const std::vector<double>& c) {
  std::vector<double> s(g.nx());
  for (int i = 0; i < g.nx(); ++i) s[i] = c[g.index(i, g.nz() - 1)];
  return s;
}

namespace {
/// Fraction of [a, b] inside [lo, hi].
double overlap(double a, double b, double lo, double hi) {
  return std::max(0.0, std::min(b, hi) - std::max(a, lo)) / (b - a);
}
}  // namespace

std::pair<double, double> end_top_fractions(const continuum::Grid& g, const std::vector<double>& c, double top_layer,
                                            double end_zone) {
  double total = 0, left = 0, right = 0;
  for (int i = 0; i < g.nx(); ++i) {
    const double x0 = g.x_face(i), x1 = g.x_face(i + 1);
    const double wl = overlap(x0, x1, 0, end_zone), wr = overlap(x0, x1, g.length() - end_zone, g.length());
    const double h = g.h_column(i);
    for (int k = 0; k < g.nz(); ++k) {
      const double m = g.area(i, k) * c[g.index(i, k)];
      const double top = overlap(g.sigma_face(k) * h, g.sigma_face(k + 1) * h, h - top_layer, h);
      total += m;
      left += m * wl * top;
      right += m * wr * top;
    }
  }
  return total > 0 ? std::make_pair(left / total, right / total) : std::make_pair(0.0, 0.0);
}

std::vector<double> spear_profile(const continuum::Grid& g, const std::vector<double>& c, double spear_depth,
                                  double background) {
  std::vector<double> s(g.nx());
  for (int i = 0; i < g.nx(); ++i) {
    const double h = g.h_column(i);
    double sum = 0;
    for (int k = 0; k < g.nz(); ++k) {
      const double z0 = g.sigma_face(k) * h, z1 = g.sigma_face(k + 1) * h;
      sum += c[g.index(i, k)] * (z1 - z0) * overlap(z0, z1, h - spear_depth, h);
    }
    if (spear_depth > h) sum += background * (spear_depth - h);
    s[i] = sum / spear_depth;
  }
  return s;
}

}  // namespace grainscale::studies
