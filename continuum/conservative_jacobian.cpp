#include "continuum/conservative_jacobian.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace grainscale::continuum {

void conservative_band_jacobian(const Model& model, double t, std::span<const double> c, int b,
                                const std::function<void(std::size_t, std::size_t, double)>& add, TermPart part) {
  const Grid& g = model.grid();
  conservative_flux_jacobian(model, t, c, b, part, [&](std::size_t row, std::size_t col, double v) {
    add(row, col, v / g.area(static_cast<int>(row) / g.nz(), static_cast<int>(row) % g.nz()));
  });
}

void conservative_flux_jacobian(const Model& model, double t, std::span<const double> c, int b, TermPart part,
                                const std::function<void(std::size_t, std::size_t, double)>& add) {
  const Grid& g = model.grid();
  const auto n = static_cast<long>(c.size());
  const long w = std::min<long>(2L * b + 1, n);
  FaceFluxes base, perturbed;
  model.face_fluxes(t, c, base, part);
  std::vector<double> cp(c.begin(), c.end());
  std::vector<double> inc(c.size());
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  for (long j = 0; j < n; ++j) inc[j] = root_eps * std::max(std::abs(c[j]), 1e-2);

  // The one perturbed cell of group `group` within [L − b, L + b], or −1.
  auto perturbed_in_window = [&](long L, long group) -> long {
    long j = L - b + ((group - (L - b)) % w + w) % w;
    return (j >= 0 && j < n && j <= L + b) ? j : -1;
  };
  // Enter ∂F/∂c_j of a face between cells L and R into rows L and R.
  auto enter = [&](long L, long R, long j, double dF) {
    if (dF == 0) return;
    if (std::abs(L - j) <= b) add(L, j, -dF);
    if (std::abs(R - j) <= b) add(R, j, dF);
  };

  for (long group = 0; group < w; ++group) {
    for (long j = group; j < n; j += w) cp[j] = c[j] + inc[j];
    model.face_fluxes(t, cp, perturbed, part);
    for (long j = group; j < n; j += w) cp[j] = c[j];
    for (int f = 1; f < g.nx(); ++f) {
      for (int k = 0; k < g.nz(); ++k) {
        const std::size_t face = x_face(g, f, k);
        const long L = static_cast<long>(g.index(f - 1, k)), R = static_cast<long>(g.index(f, k));
        const long j = perturbed_in_window(L, group);
        if (j >= 0) enter(L, R, j, (perturbed.x[face] - base.x[face]) / inc[j]);
      }
    }
    for (int i = 0; i < g.nx(); ++i) {
      for (int m = 1; m < g.nz(); ++m) {
        const std::size_t face = s_face(g, i, m);
        const long L = static_cast<long>(g.index(i, m - 1)), R = static_cast<long>(g.index(i, m));
        const long j = perturbed_in_window(L, group);
        if (j >= 0) enter(L, R, j, (perturbed.s[face] - base.s[face]) / inc[j]);
      }
    }
  }
}

}  // namespace grainscale::continuum
