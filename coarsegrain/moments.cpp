#include "coarsegrain/moments.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace grainscale::cg {

using dem::Vec3;

Moments::Moments(int n_species, std::size_t n_cells) : species(n_species), cells(n_cells) {
  const std::size_t n = static_cast<std::size_t>(n_species + 1) * n_cells;
  mass.assign(n, 0.0);
  volume.assign(n, 0.0);
  number.assign(n, 0.0);
  fluctuation.assign(n, 0.0);
  momentum.assign(n, Vec3{});
}

void Moments::add(const Moments& o) {
  if (snapshots == 0 && mass.empty()) {
    *this = o;
    return;
  }
  if (o.species != species || o.cells != cells) throw std::invalid_argument("Moments::add: different grids or species");
  for (std::size_t k = 0; k < mass.size(); ++k) {
    const double ra = mass[k], rb = o.mass[k], r = ra + rb;
    if (ra > 0 && rb > 0) {
      const Vec3 du = (1.0 / ra) * momentum[k] - (1.0 / rb) * o.momentum[k];
      fluctuation[k] += o.fluctuation[k] + ra * rb / r * norm2(du);
    } else {
      fluctuation[k] += o.fluctuation[k];
    }
    mass[k] = r;
    volume[k] += o.volume[k];
    number[k] += o.number[k];
    momentum[k] += o.momentum[k];
  }
  snapshots += o.snapshots;
  time += o.time;
  excluded_mass += o.excluded_mass;
  excluded_count += o.excluded_count;
}

void Moments::average() {
  if (snapshots <= 1) return;
  const double s = 1.0 / snapshots;
  for (std::size_t k = 0; k < mass.size(); ++k) {
    mass[k] *= s;
    volume[k] *= s;
    number[k] *= s;
    fluctuation[k] *= s;
    momentum[k] *= s;
  }
  time *= s;
  excluded_mass *= s;
  excluded_count = static_cast<std::size_t>(std::llround(static_cast<double>(excluded_count) * s));
  snapshots = 1;
}

namespace {

/// Every particle's 1-D weights along the three axes, in fixed-stride slots (no allocation per
/// particle in the scatter loops, and each particle's slot is written by one thread only).
struct Stencils {
  std::array<int, 3> stride{};
  std::vector<std::array<int, 3>> first, count;
  std::vector<double> weight;  // particle p, axis a: weight[p * total + offset[a] + i]
  std::array<int, 3> offset{};
  int total = 0;

  const double* w(std::size_t p, int a) const {
    return weight.data() + p * static_cast<std::size_t>(total) + static_cast<std::size_t>(offset[static_cast<std::size_t>(a)]);
  }
};

Stencils make_stencils(const std::vector<std::size_t>& inside, const CgParticles& particles, const Grid& grid,
                       const Kernel& kernel) {
  Stencils st;
  for (int a = 0; a < 3; ++a) {
    const auto s = static_cast<std::size_t>(a);
    const int most = static_cast<int>(std::floor(2 * kernel.cutoff() / grid.spacing(a))) + 2;
    st.stride[s] = grid.resolved(a) ? std::min(grid.cells[s], most) : 1;
    st.offset[s] = st.total;
    st.total += st.stride[s];
  }
  const std::size_t n = inside.size();
  st.first.resize(n);
  st.count.resize(n);
  st.weight.assign(n * static_cast<std::size_t>(st.total), 0.0);
#pragma omp parallel
  {
    AxisWeights aw;
#pragma omp for schedule(static)
    for (std::size_t q = 0; q < n; ++q) {
      const Vec3& x = particles.position[inside[q]];
      for (int a = 0; a < 3; ++a) {
        const auto s = static_cast<std::size_t>(a);
        axis_weights(kernel, grid, a, x[a], aw);
        st.first[q][s] = aw.first;
        st.count[q][s] = static_cast<int>(aw.weight.size());
        std::copy(aw.weight.begin(), aw.weight.end(), st.weight.begin() + static_cast<std::ptrdiff_t>(q * static_cast<std::size_t>(st.total) + static_cast<std::size_t>(st.offset[s])));
      }
    }
  }
  return st;
}

/// Calls f(q, slab cell, weight) for every particle q whose stencil reaches x-slab i, and every cell
/// of the slab it reaches (slab cell j + ny k is grid cell (i, j, k)), in a fixed order: particles by
/// the slab their stencil starts in, then by index.
template <class F>
void for_each_in_slab(int i, const Stencils& st, const std::vector<std::size_t>& bucket_start,
                      const std::vector<std::size_t>& by_first_x, const Grid& grid, F&& f) {
  const int b0 = std::max(0, i - st.stride[0] + 1);
  const int ny = grid.cells[1];
  for (std::size_t r = bucket_start[static_cast<std::size_t>(b0)]; r < bucket_start[static_cast<std::size_t>(i) + 1]; ++r) {
    const std::size_t q = by_first_x[r];
    const int di = i - st.first[q][0];
    if (di >= st.count[q][0]) continue;
    const double wx = st.w(q, 0)[di];
    const double* wy = st.w(q, 1);
    const double* wz = st.w(q, 2);
    for (int c = 0; c < st.count[q][2]; ++c) {
      const double wxz = wx * wz[c];
      const std::size_t row = static_cast<std::size_t>(ny) * static_cast<std::size_t>(st.first[q][2] + c);
      for (int b = 0; b < st.count[q][1]; ++b) {
        f(q, row + static_cast<std::size_t>(st.first[q][1] + b), wxz * wy[b]);
      }
    }
  }
}

}  // namespace

Moments coarse_grain(const CgParticles& particles, int n_species, const Grid& grid, const Kernel& kernel) {
  if (!(kernel.width > 0) || !std::isfinite(kernel.width)) throw std::invalid_argument("kernel width must be positive");
  Moments m(n_species, grid.size());
  m.snapshots = 1;
  m.time = particles.time;

  std::vector<std::size_t> inside;
  inside.reserve(particles.size());
  for (std::size_t p = 0; p < particles.size(); ++p) {
    if (grid.contains(particles.position[p])) {
      inside.push_back(p);
    } else {
      m.excluded_mass += particles.mass[p];
      ++m.excluded_count;
    }
  }
  const Stencils st = make_stencils(inside, particles, grid, kernel);

  // Counting sort of the particles by the first x cell of their stencil (stable: index order within).
  const int nx = grid.cells[0];
  std::vector<std::size_t> bucket_start(static_cast<std::size_t>(nx) + 1, 0), by_first_x(inside.size());
  for (std::size_t q = 0; q < inside.size(); ++q) ++bucket_start[static_cast<std::size_t>(st.first[q][0]) + 1];
  for (int i = 0; i < nx; ++i) bucket_start[static_cast<std::size_t>(i) + 1] += bucket_start[static_cast<std::size_t>(i)];
  {
    std::vector<std::size_t> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (std::size_t q = 0; q < inside.size(); ++q) by_first_x[fill[static_cast<std::size_t>(st.first[q][0])]++] = q;
  }

  const double inv_v = 1.0 / grid.cell_volume();
  const int mix = m.mixture();
  const int rows = n_species + 1;
  const std::size_t slab_cells = static_cast<std::size_t>(grid.cells[1]) * static_cast<std::size_t>(grid.cells[2]);
  // Slabs are disjoint, so threads never share a cell. Each slab is summed into a small contiguous
  // buffer (cache-resident: [slab cell][row][mass, volume, number, jx, jy, jz]) and copied out; the
  // order of additions per cell is the particle order either way.
  // Pass 1: mass, volume, number, momentum.
#pragma omp parallel
  {
    std::vector<double> acc;
#pragma omp for schedule(dynamic, 1)
    for (int i = 0; i < nx; ++i) {
      acc.assign(slab_cells * static_cast<std::size_t>(rows) * 6, 0.0);
      for_each_in_slab(i, st, bucket_start, by_first_x, grid, [&](std::size_t q, std::size_t cell, double w) {
        const std::size_t p = inside[q];
        const double mw = particles.mass[p] * w * inv_v, vw = particles.volume[p] * w * inv_v, nw = particles.number[p] * w * inv_v;
        const Vec3& v = particles.velocity[p];
        for (const int row : {particles.species[p], mix}) {
          double* a = acc.data() + (cell * static_cast<std::size_t>(rows) + static_cast<std::size_t>(row)) * 6;
          a[0] += mw;
          a[1] += vw;
          a[2] += nw;
          a[3] += mw * v.x;
          a[4] += mw * v.y;
          a[5] += mw * v.z;
        }
      });
      for (std::size_t cell = 0; cell < slab_cells; ++cell) {
        const std::size_t g = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * cell;  // grid index of (i, j, k)
        for (int row = 0; row < rows; ++row) {
          const double* a = acc.data() + (cell * static_cast<std::size_t>(rows) + static_cast<std::size_t>(row)) * 6;
          const std::size_t k = m.at(row, g);
          m.mass[k] = a[0];
          m.volume[k] = a[1];
          m.number[k] = a[2];
          m.momentum[k] = {a[3], a[4], a[5]};
        }
      }
    }
  }
  // Pass 2: fluctuations about the species and the mixture velocity of each cell.
#pragma omp parallel
  {
    std::vector<double> acc;
    std::vector<Vec3> u;
#pragma omp for schedule(dynamic, 1)
    for (int i = 0; i < nx; ++i) {
      acc.assign(slab_cells * static_cast<std::size_t>(rows), 0.0);
      u.resize(acc.size());
      for (std::size_t cell = 0; cell < slab_cells; ++cell) {
        const std::size_t g = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * cell;
        for (int row = 0; row < rows; ++row) {
          const std::size_t k = m.at(row, g);
          u[cell * static_cast<std::size_t>(rows) + static_cast<std::size_t>(row)] = m.mass[k] > 0 ? (1.0 / m.mass[k]) * m.momentum[k] : Vec3{};
        }
      }
      for_each_in_slab(i, st, bucket_start, by_first_x, grid, [&](std::size_t q, std::size_t cell, double w) {
        const std::size_t p = inside[q];
        const double mw = particles.mass[p] * w * inv_v;
        const Vec3& v = particles.velocity[p];
        for (const int row : {particles.species[p], mix}) {
          const std::size_t a = cell * static_cast<std::size_t>(rows) + static_cast<std::size_t>(row);
          acc[a] += mw * norm2(v - u[a]);
        }
      });
      for (std::size_t cell = 0; cell < slab_cells; ++cell) {
        const std::size_t g = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * cell;
        for (int row = 0; row < rows; ++row) m.fluctuation[m.at(row, g)] = acc[cell * static_cast<std::size_t>(rows) + static_cast<std::size_t>(row)];
      }
    }
  }
  return m;
}

}  // namespace grainscale::cg
