#include "coarsegrain/fields.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace grainscale::cg {

using dem::Vec3;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const Vec3 kNaNVec{kNaN, kNaN, kNaN};

SpeciesFields species_fields(const Moments& m, int s) {
  SpeciesFields f;
  const auto begin = static_cast<std::ptrdiff_t>(m.at(s, 0)), end = begin + static_cast<std::ptrdiff_t>(m.cells);
  f.density.assign(m.mass.begin() + begin, m.mass.begin() + end);
  f.volume_fraction.assign(m.volume.begin() + begin, m.volume.begin() + end);
  f.number_density.assign(m.number.begin() + begin, m.number.begin() + end);
  f.velocity.resize(m.cells);
  f.temperature.resize(m.cells);
  for (std::size_t c = 0; c < m.cells; ++c) {
    const std::size_t k = m.at(s, c);
    const double rho = m.mass[k];
    f.velocity[c] = rho > 0 ? (1.0 / rho) * m.momentum[k] : kNaNVec;
    f.temperature[c] = rho > 0 ? m.fluctuation[k] / (3 * rho) : kNaN;
  }
  return f;
}

/// d u / d x_axis at cell (i, j, k) from the neighbours along `axis`; NaN without usable neighbours.
Vec3 derivative(const Grid& g, const std::vector<double>& rho, const std::vector<Vec3>& u, int axis, std::array<int, 3> ijk) {
  const auto a = static_cast<std::size_t>(axis);
  const int n = g.cells[a];
  auto occupied = [&](int shift) {
    std::array<int, 3> q = ijk;
    q[a] += shift;
    if (q[a] < 0 || q[a] >= n) return std::size_t(-1);
    const std::size_t c = g.index(q[0], q[1], q[2]);
    return rho[c] > 0 ? c : std::size_t(-1);
  };
  const std::size_t here = occupied(0), minus = occupied(-1), plus = occupied(+1);
  const double h = g.spacing(axis);
  const std::size_t none = std::size_t(-1);
  if (minus != none && plus != none) return (0.5 / h) * (u[plus] - u[minus]);
  if (here == none) return kNaNVec;
  if (plus != none) return (1.0 / h) * (u[plus] - u[here]);
  if (minus != none) return (1.0 / h) * (u[here] - u[minus]);
  return kNaNVec;
}

}  // namespace

double shear_rate(const std::array<double, 9>& L) {
  double D[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) D[a][b] = 0.5 * (L[static_cast<std::size_t>(3 * a + b)] + L[static_cast<std::size_t>(3 * b + a)]);
  const double third_trace = (D[0][0] + D[1][1] + D[2][2]) / 3.0;
  for (int a = 0; a < 3; ++a) D[a][a] -= third_trace;
  double dd = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) dd += D[a][b] * D[a][b];
  return std::sqrt(2 * dd);
}

Fields derive_fields(const Moments& m, const Grid& grid, const SpeciesTable& table, const FieldOptions& options) {
  if (m.cells != grid.size() || m.species != table.size()) throw std::invalid_argument("derive_fields: moments do not match grid/species");
  Fields f;
  f.grid = grid;
  f.time = m.time;
  f.snapshots = m.snapshots;
  f.species_names = table.names;
  for (int s = 0; s < table.size(); ++s) f.species.push_back(species_fields(m, s));
  f.mixture = species_fields(m, m.mixture());

  const std::size_t n = m.cells;
  f.chaff_volume_concentration.assign(n, kNaN);
  f.chaff_number_concentration.assign(n, kNaN);
  f.chaff_mass_concentration.assign(n, kNaN);
  f.chaff_velocity.assign(n, kNaNVec);
  f.segregation_flux.assign(n, kNaNVec);
  for (std::size_t c = 0; c < n; ++c) {
    const std::size_t mix = m.at(m.mixture(), c);
    if (!(m.mass[mix] > 0)) continue;
    double phi = 0, num = 0, rho = 0;
    Vec3 j;
    for (int s = 0; s < table.size(); ++s) {
      if (!table.chaff[static_cast<std::size_t>(s)]) continue;
      const std::size_t k = m.at(s, c);
      phi += m.volume[k];
      num += m.number[k];
      rho += m.mass[k];
      j += m.momentum[k];
    }
    f.chaff_volume_concentration[c] = m.volume[mix] > 0 ? phi / m.volume[mix] : kNaN;
    f.chaff_number_concentration[c] = m.number[mix] > 0 ? num / m.number[mix] : kNaN;
    f.chaff_mass_concentration[c] = rho / m.mass[mix];
    if (rho > 0) {
      f.chaff_velocity[c] = (1.0 / rho) * j;
      f.segregation_flux[c] = f.chaff_volume_concentration[c] * (f.chaff_velocity[c] - f.mixture.velocity[c]);
    } else {
      f.segregation_flux[c] = Vec3{};
    }
  }

  // Velocity gradient and shear rate of the mixture velocity.
  f.velocity_gradient.assign(n, {});
  f.shear_rate.assign(n, kNaN);
  for (int k = 0; k < grid.cells[2]; ++k)
    for (int j = 0; j < grid.cells[1]; ++j)
      for (int i = 0; i < grid.cells[0]; ++i) {
        const std::size_t c = grid.index(i, j, k);
        std::array<double, 9>& L = f.velocity_gradient[c];
        if (!(f.mixture.density[c] > 0)) {
          L.fill(kNaN);
          continue;
        }
        for (int b = 0; b < 3; ++b) {
          if (!grid.resolved(b)) continue;  // averaged axis: no variation
          const Vec3 d = derivative(grid, f.mixture.density, f.mixture.velocity, b, {i, j, k});
          for (int a = 0; a < 3; ++a) L[static_cast<std::size_t>(3 * a + b)] = d[a];
        }
        f.shear_rate[c] = shear_rate(L);
      }

  // Free-surface height per (x, y) column.
  if (grid.dimension >= 2) {
    const int nx = grid.cells[0], ny = grid.cells[1], nz = grid.cells[2];
    f.surface_height.assign(static_cast<std::size_t>(nx * ny), kNaN);
    const std::vector<double>& phi = f.mixture.volume_fraction;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        double bulk = options.bulk_volume_fraction;
        if (!(bulk > 0)) {
          bulk = 0;
          for (int k = 0; k < nz; ++k) bulk = std::max(bulk, phi[grid.index(i, j, k)]);
        }
        if (!(bulk > 0)) continue;
        const double threshold = options.surface_fraction * bulk;
        double h = kNaN;
        for (int k = nz - 1; k >= 0; --k) {
          const double here = phi[grid.index(i, j, k)];
          if (here < threshold) continue;
          if (k == nz - 1) {
            h = grid.upper(2);
          } else {
            const double above = phi[grid.index(i, j, k + 1)];
            h = grid.centre(2, k) + (here - threshold) / (here - above) * grid.spacing(2);
          }
          break;
        }
        f.surface_height[static_cast<std::size_t>(i + nx * j)] = h;
      }
  }
  return f;
}

}  // namespace grainscale::cg
