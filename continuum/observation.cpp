#include "continuum/observation.hpp"

#include <algorithm>
#include <cmath>

namespace grainscale::continuum {

SurfaceCoverage::SurfaceCoverage(double kappa, double delta)
    : params_("observation", {{"kappa", "1/m", 100.0, 0.0, 1e6, 10.0, 2000.0, "coverage = 1 − exp(−κ ∫top c dz)"},
                              {"delta", "m", 4e-3, 1e-6, 1.0, 1e-3, 2e-2, "thickness of the visible top layer"}}) {
  params_.set("kappa", kappa);
  params_.set("delta", delta);
}

std::vector<double> SurfaceCoverage::top_layer_content(const Grid& g, std::span<const double> c) const {
  const double delta = params_.get("delta");
  std::vector<double> content(g.nx(), 0.0);
  for (int i = 0; i < g.nx(); ++i) {
    const double h = g.h_column(i), dz = g.dsigma() * h, bottom = h - delta;
    double sum = 0;
    for (int k = g.nz() - 1; k >= 0; --k) {
      const double z_lo = k * dz, z_hi = (k + 1) * dz;
      const double overlap = std::min(z_hi, h) - std::max(z_lo, bottom);
      if (overlap <= 0) break;
      sum += overlap * c[g.index(i, k)];
    }
    content[i] = sum;
  }
  return content;
}

std::vector<double> SurfaceCoverage::coverage(const Grid& g, std::span<const double> c) const {
  std::vector<double> cov = top_layer_content(g, c);
  const double kappa = params_.get("kappa");
  for (double& v : cov) v = 1 - std::exp(-kappa * v);
  return cov;
}

}  // namespace grainscale::continuum
