#include "dem/parallel.hpp"
#include "dem/neighbor_list.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace grainscale::dem {

namespace {
double component(const Vec3& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }
}  // namespace

int NeighborList::cell_of(const Vec3& x) const {
  int i[3];
  // Clamped before the conversion: a particle outside the grid (a stray, see sort_by_cell) lands in
  // an edge cell however far away it is.
  for (int k = 0; k < 3; ++k) {
    const double u = (component(x, axis_[k]) - component(origin_, axis_[k])) / cell_;
    i[k] = static_cast<int>(std::clamp(u, 0.0, static_cast<double>(n_[k] - 1)));
  }
  return (i[2] * n_[1] + i[1]) * n_[0] + i[0];
}

NeighborList::GridBounds NeighborList::grid_bounds(const std::vector<Vec3>& x, const std::vector<double>& radius, std::size_t n,
                                                    double skin) {
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, lo_z = lo_x;
  double hi_x = -lo_x, hi_y = -lo_x, hi_z = -lo_x, r_max = 0;
  int nonfinite = 0;  // (min and max pass NaN over, so it is counted apart)
#pragma omp parallel for if(n >= parallel_min_items()) reduction(min : lo_x, lo_y, lo_z) reduction(max : hi_x, hi_y, hi_z, r_max) reduction(+ : nonfinite)
  for (std::size_t i = 0; i < n; ++i) {
    lo_x = std::min(lo_x, x[i].x), lo_y = std::min(lo_y, x[i].y), lo_z = std::min(lo_z, x[i].z);
    hi_x = std::max(hi_x, x[i].x), hi_y = std::max(hi_y, x[i].y), hi_z = std::max(hi_z, x[i].z);
    r_max = std::max(r_max, radius[i]);
    nonfinite += !is_finite(x[i]);
  }
  if (n == 0) lo_x = lo_y = lo_z = hi_x = hi_y = hi_z = 0;
  // Only a blown-up state has positions that are not finite or spread over more than the largest
  // double; cell indices cannot be computed for it (the caller reports the blow-up).
  if (nonfinite > 0 || !std::isfinite(hi_x - lo_x) || !std::isfinite(hi_y - lo_y) || !std::isfinite(hi_z - lo_z)) {
    throw std::overflow_error("particle positions are not finite or spread over more than 1e308 m");
  }

  // Cells at least one interaction range wide; the particle count bounds the grid size.
  GridBounds b;
  b.r_max = r_max;
  b.cell = std::max(2.0 * r_max + skin, 1e-12);
  b.max_cells = std::max<double>(64.0, 8.0 * static_cast<double>(n));
  // A stray (a grain thrown out of an open container and falling away) stretches the box: widening
  // the cells to cover it would put hundreds of neighbours in every cell and slow the whole run by
  // orders of magnitude. Grid the core instead, the 1st to 99th percentile of the positions on each
  // axis plus a cell, and let the particles beyond it fall into the edge cells (cell_of clamps).
  // Clamping moves no two points further apart on any axis, so pairs within range still lie in
  // adjacent cells: the list is exact, only the strays' own search is longer.
  double* lo = b.lo;
  double* hi = b.hi;
  lo[0] = lo_x, lo[1] = lo_y, lo[2] = lo_z, hi[0] = hi_x, hi[1] = hi_y, hi[2] = hi_z;
  if (GridBounds::product(b.cells_along(b.cell)) > b.max_cells && n >= 100) {
    const std::size_t k = n / 100;
    scratch_.resize(n);
    for (int a = 0; a < 3; ++a) {
      for (std::size_t i = 0; i < n; ++i) scratch_[i] = component(x[i], a);
      std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(k), scratch_.begin() + static_cast<std::ptrdiff_t>(n));
      const double q_lo = scratch_[k];
      std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(n - 1 - k), scratch_.begin() + static_cast<std::ptrdiff_t>(n));
      const double q_hi = scratch_[n - 1 - k];
      if (q_lo - b.cell > lo[a]) lo[a] = q_lo - b.cell, b.trimmed = true;
      if (q_hi + b.cell < hi[a]) hi[a] = q_hi + b.cell, b.trimmed = true;
    }
  }
  return b;
}

const std::vector<std::uint32_t>& NeighborList::sort_by_cell(const Particles& p, double skin) {
  const std::size_t n = p.size();
  bounds_ = grid_bounds(p.x, p.radius, n, skin);
  const GridBounds& b = bounds_;
  cell_ = b.cell;
  // If even the core is too large a grid (a sparse cloud), widen the cells.
  for (;;) {
    const std::array<double, 3> f = b.cells_along(cell_);
    if (GridBounds::product(f) <= b.max_cells) {
      const int counts[3] = {static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2])};
      // Fewest cells fastest, most cells slowest (ties keep x, y, z order). An insertion sort of
      // three: std::stable_sort would allocate a buffer in the step loop.
      axis_[0] = 0, axis_[1] = 1, axis_[2] = 2;
      for (int k = 1; k < 3; ++k)
        for (int j = k; j > 0 && counts[axis_[j]] < counts[axis_[j - 1]]; --j) std::swap(axis_[j], axis_[j - 1]);
      for (int k = 0; k < 3; ++k) n_[k] = counts[axis_[k]];
      break;
    }
    cell_ *= 1.5;
  }
  origin_ = {b.lo[0], b.lo[1], b.lo[2]};
  const std::size_t cells = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];

  cell_index_.resize(n);
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static)
  for (std::size_t i = 0; i < n; ++i) cell_index_[i] = cell_of(p.x[i]);

  // Stable counting sort by cell.
  cell_start_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++cell_start_[cell_index_[i] + 1];
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  rev_fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) order_[rev_fill_[cell_index_[i]]++] = static_cast<std::uint32_t>(i);
  return order_;
}

void NeighborList::build(Particles& p, double skin, const std::vector<std::uint32_t>& new_to_old) {
  skins_.clear();
  skin_ = smallest_skin_ = skin;
  build_rows(p, new_to_old);
}

void NeighborList::build(Particles& p, const std::vector<double>& skins, const std::vector<std::uint32_t>& new_to_old) {
  assert(skins.size() == p.size());
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (const double s : skins) lo = std::min(lo, s), hi = std::max(hi, s);
  if (skins.empty()) lo = 0;
  skin_ = hi, smallest_skin_ = lo;
  // One skin for all: the list and its slack are those of build(p, skin) bit for bit.
  if (lo == hi) {
    skins_.clear();
  } else {
    skins_.assign(skins.begin(), skins.end());
  }
  build_rows(p, new_to_old);
}

void NeighborList::spread_to_adjacent_cells(const Particles& p, const std::vector<double>& own, double floor,
                                            std::vector<double>& out) const {
  // Serial: only the particles above the floor spread (a few in a bed at rest; dem/adaptive_skin.hpp
  // keeps them to about one in a hundred), each over its 27 cells. max() in any order: the same result.
  const std::size_t n = p.size();
  assert(own.size() == n && cell_start_.size() == static_cast<std::size_t>(n_[0]) * n_[1] * n_[2] + 1);
  out.assign(own.begin(), own.end());
  for (std::size_t i = 0; i < n; ++i) {
    if (!(own[i] > floor)) continue;
    const int c = cell_of(p.x[i]);
    const int i0 = c % n_[0], i1 = (c / n_[0]) % n_[1], i2 = c / (n_[0] * n_[1]);
    for (int s = std::max(i2 - 1, 0); s <= std::min(i2 + 1, n_[2] - 1); ++s)
      for (int m = std::max(i1 - 1, 0); m <= std::min(i1 + 1, n_[1] - 1); ++m) {
        const int row = (s * n_[1] + m) * n_[0];
        const std::uint32_t j1 = cell_start_[row + std::min(i0 + 1, n_[0] - 1) + 1];
        for (std::uint32_t j = cell_start_[row + std::max(i0 - 1, 0)]; j < j1; ++j) out[j] = std::max(out[j], own[i]);
      }
  }
}

void NeighborList::build_rows(Particles& p, const std::vector<std::uint32_t>& new_to_old) {
  const std::size_t n = p.size();
  const double skin = skin_;
  const double* own = skins_.empty() ? nullptr : skins_.data();
  // The pair search below looks no further than the adjacent cells.
  assert(cell_ >= 2 * bounds_.r_max + skin || n == 0);
  start_.swap(old_start_);
  partner_.swap(old_partner_);
  shear_.swap(old_shear_);
  rolling_.swap(old_rolling_);
  // Particles added since the last build sit at slots >= n_old before sorting: they start without
  // history; every pair of particles that were already there keeps its history.
  const std::size_t n_old = old_start_.empty() ? 0 : old_start_.size() - 1;
  const bool carry = n_old > 0 && n_old <= n;

  // Sphere i's partners after it (j > i) into out[0, count): every candidate of the rows scanned is
  // stored, and the count advanced only for a pair within reach, so no branch follows the distance
  // test, whose outcome follows no pattern (in the 2x platform box a third of build_rows' samples sat
  // on that branch and the push_back behind it). The arrays as plain pointers, and i's own values in
  // locals: stored through a vector, each partner made GCC load them again. Returns the count; `out`
  // must have room for the rows' bound (every candidate).
  const Vec3* const x = p.x.data();
  const double* const radius = p.radius.data();
  const std::uint32_t* const body = p.body.data();
  const std::uint32_t* const cell_start = cell_start_.data();
  constexpr int kMostRows = 5;  // two rows in i's own layer (its row and the next), three in the next layer
  struct Rows {  // the slot ranges [j0[r], j1[r]) of i's candidates, one per row of cells
    std::uint32_t j0[kMostRows], j1[kMostRows];
    int rows = 0;
    std::uint32_t bound = 0;
  };
  auto rows_of = [&](std::size_t i) {
    Rows r;
    const int c = cell_of(x[i]);
    const int i0 = c % n_[0], i1 = (c / n_[0]) % n_[1], i2 = c / (n_[0] * n_[1]);
    // Only partners after i (j > i): the rows before i's own (lower s, or the same s and lower m)
    // hold only slots before it, since slots are in cell order; they are not scanned.
    for (int s = i2; s <= std::min(i2 + 1, n_[2] - 1); ++s)
      for (int m = s == i2 ? i1 : std::max(i1 - 1, 0); m <= std::min(i1 + 1, n_[1] - 1); ++m) {
        // The cells of one row (fast axis i0-1..i0+1) are contiguous in slot order: one range covers them.
        const int row = (s * n_[1] + m) * n_[0];
        const std::uint32_t j0 = std::max<std::uint32_t>(cell_start[row + std::max(i0 - 1, 0)], static_cast<std::uint32_t>(i + 1));
        const std::uint32_t j1 = cell_start[row + std::min(i0 + 1, n_[0] - 1) + 1];
        if (j1 <= j0) continue;
        assert(r.rows < kMostRows);
        r.j0[r.rows] = j0, r.j1[r.rows] = j1, ++r.rows;
        r.bound += j1 - j0;
      }
    return r;
  };
  auto list_partners = [&]<bool kOwn>(std::size_t i, const Rows& r, std::uint32_t* out) {
    const Vec3 xi = x[i];
    const double ri = radius[i], own_i = kOwn ? own[i] : 0.0;
    const std::uint32_t bi = body[i];
    std::uint32_t count = 0;
    for (int q = 0; q < r.rows; ++q) {
      for (std::uint32_t j = r.j0[q]; j < r.j1[q]; ++j) {
        // (One skin for all: the sum as it always was, so such a list is the same bit for bit.)
        const double cut = kOwn ? ri + radius[j] + 0.5 * (own_i + own[j]) : ri + radius[j] + skin;
        out[count] = j;
        count += static_cast<std::uint32_t>((body[j] != bi) & (norm2(x[j] - xi) < cut * cut));  // no contacts inside a body
      }
    }
    return count;
  };

  // One scan of the cells per particle: each thread lists the partners of a contiguous block of
  // rows into its own buffer, the row starts are summed, and the buffers are copied into place (a
  // count pass and a fill pass used to scan twice: a build cost ~6 steps' work in a swinging box,
  // perf, docs/performance.md). Rows in order, each row's partners in scan order: the same list
  // for any thread count.
  count_.resize(n);
  start_.resize(n + 1);
  const bool parallel = n >= parallel_min_items();
  thread_partners_.resize(static_cast<std::size_t>(parallel ? omp_get_max_threads() : 1));
#pragma omp parallel if(parallel)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t threads = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t first = n * t / threads, last = n * (t + 1) / threads;
    // The buffer keeps its size from build to build (grown, never shrunk); `used` entries are this build's.
    std::vector<std::uint32_t>& buffer = thread_partners_[t];
    std::size_t used = 0;
    for (std::size_t i = first; i < last; ++i) {
      const Rows r = rows_of(i);
      if (buffer.size() < used + r.bound) buffer.resize(std::max(2 * buffer.size(), used + r.bound));
      const std::uint32_t found = own ? list_partners.template operator()<true>(i, r, buffer.data() + used)
                                      : list_partners.template operator()<false>(i, r, buffer.data() + used);
      count_[i] = found;
      used += found;
    }
#pragma omp barrier
#pragma omp single
    {
      start_[0] = 0;
      for (std::size_t i = 0; i < n; ++i) start_[i + 1] = start_[i] + count_[i];
      partner_.resize(start_[n]);
      shear_.resize(start_[n]);
      rolling_.resize(rolling_springs_ ? start_[n] : 0);
    }
    std::copy(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(used), partner_.begin() + start_[first]);
    for (std::size_t i = first; i < last; ++i) {
      const std::uint32_t oi = carry ? new_to_old[i] : 0;
      for (std::uint32_t k = start_[i]; k < start_[i + 1]; ++k) {
        shear_[k] = {};
        if (rolling_springs_) rolling_[k] = {};
        if (carry && oi < n_old) {
          const std::uint32_t oj = new_to_old[partner_[k]];
          if (oj >= n_old) continue;  // added since: no history
          // The pair was stored under the one of the two that came first in the old order: under i
          // (the same history) or under j (the history of the pair seen from j: negated, exactly).
          const bool same_owner = oi < oj;
          const std::uint32_t row = same_owner ? oi : oj, other = same_owner ? oj : oi;
          for (std::uint32_t m = old_start_[row]; m < old_start_[row + 1]; ++m) {
            if (old_partner_[m] == other) {
              shear_[k] = same_owner ? old_shear_[m] : -old_shear_[m];
              if (rolling_springs_) rolling_[k] = same_owner ? old_rolling_[m] : -old_rolling_[m];
              break;
            }
          }
        }
      }
    }
  }

  index_partners(n);

#pragma omp parallel for if(n >= parallel_min_items()) schedule(static)
  for (std::size_t i = 0; i < n; ++i) p.x_at_build[i] = p.x[i];
  assign_stray_slack(p, n, bounds_);
  ++builds_;
  ++generation_;
}

void NeighborList::assign_stray_slack(const Particles& p, std::size_t n, const GridBounds& b) {
  // A stray far from every other particle (and from every static wall: the force loop asks all of
  // them for it, force_field.cpp) may move further than skin/2 before the list is wrong. With gap_i
  // the smallest surface gap from i to any particle of another body at the build, i may move
  //   allow_i = max(skin/2, gap_i/2)
  // and the list stays exact: a pair not listed is at least gap_ij >= max(gap_i, gap_j) >= skin
  // apart, and allow_i + allow_j <= gap_ij (both halves, or gap_i/2 + skin/2 <= gap_i when
  // gap_i >= skin). stale() sees d_i² − slack2_i with slack2_i = allow_i² − skin²/4, so the others'
  // test is unchanged bit for bit. Only particles outside the gridded core (strays, sort_by_cell)
  // are candidates; the particles inside the core box are at least the distance to the box away.
  // With a skin per particle (skin the largest), a particle of skin s_i that is not a stray may move
  // allow_i = s_i/2 (slack2_i <= 0), and a stray allow_i = gap_i/2 where gap_i >= skin: then
  // gap_i/2 + s_j/2 <= gap_i <= gap_ij for any j, and s_i/2 + s_j/2 <= gap_ij for a pair not listed.
  const double half = 0.5 * skin_;
  slack2_.clear();
  if (!skins_.empty()) {
    slack2_.resize(n);
    for (std::size_t i = 0; i < n; ++i) slack2_[i] = 0.25 * skins_[i] * skins_[i] - half * half;
  }
  if (!b.trimmed) return;
  outside_.clear();
  candidates_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const double d2 = b.distance2(p.x_at_build[i]);
    if (d2 == 0) continue;
    outside_.push_back(static_cast<std::uint32_t>(i));
    const double reach = p.radius[i] + b.r_max + skin_;
    if (d2 > reach * reach) candidates_.push_back(static_cast<std::uint32_t>(i));
  }
  // Beyond a few dozen the edge of a wide bed, not strays, is outside the core: no slack (the cost
  // below is candidates x outside).
  if (candidates_.empty() || candidates_.size() > kMaxStrays) return;
  if (slack2_.empty()) slack2_.assign(n, 0.0);
  for (const std::uint32_t i : candidates_) {
    const Vec3& x = p.x_at_build[i];
    double gap = std::sqrt(b.distance2(x)) - p.radius[i] - b.r_max;
    for (const std::uint32_t j : outside_) {
      if (j == i || p.body[j] == p.body[i]) continue;
      gap = std::min(gap, std::sqrt(norm2(p.x_at_build[j] - x)) - p.radius[i] - p.radius[j]);
    }
    const double own_half = skins_.empty() ? half : 0.5 * skins_[i];
    const double allow = gap >= skin_ ? std::max(half, 0.5 * gap) : own_half;
    slack2_[i] = allow * allow - half * half;
  }
}

void NeighborList::index_partners(std::size_t n) {
  // Reverse index, filled in entry order so the gather order is fixed (a function of partner_ alone).
  rev_start_.assign(n + 1, 0);
  for (std::uint32_t k = 0; k < partner_.size(); ++k) ++rev_start_[partner_[k] + 1];
  for (std::size_t i = 0; i < n; ++i) rev_start_[i + 1] += rev_start_[i];
  rev_fill_.assign(rev_start_.begin(), rev_start_.end() - 1);
  rev_entry_.resize(partner_.size());
  rev_position_.resize(partner_.size());
  rev_owner_.resize(partner_.size());
  for (std::uint32_t k = 0; k < partner_.size(); ++k) {
    const std::uint32_t r = rev_fill_[partner_[k]]++;
    rev_entry_[r] = k;
    rev_position_[k] = r;
    rev_owner_[r] = partner_[k];
  }
  owner_.resize(partner_.size());
  reach_.resize(n + 1);
  std::uint32_t reach = 0;  // 1 + the furthest partner of the rows so far
  for (std::size_t i = 0; i < n; ++i) {
    reach_[i] = reach;
    std::fill(owner_.begin() + start_[i], owner_.begin() + start_[i + 1], static_cast<std::uint32_t>(i));
    for (std::uint32_t k = start_[i]; k < start_[i + 1]; ++k) reach = std::max(reach, partner_[k] + 1);
  }
  reach_[n] = reach;
}

void NeighborList::restore(const Particles& p, double skin, std::vector<double> skins, std::vector<std::uint32_t> start,
                           std::vector<std::uint32_t> partner, const std::vector<ContactHistory>& history,
                           std::size_t builds) {
  // The invariants build() guarantees and the force loop relies on (no bounds checks there). The list
  // may cover fewer particles than `p` holds: those added since the build, at the end, have no entries
  // yet (stale() then asks for a rebuild, which carries the histories over).
  auto bad = [](const std::string& why) { throw std::invalid_argument("neighbour list: " + why); };
  if (start.empty() || start.size() > p.size() + 1) {
    bad(std::to_string(start.size()) + " row starts for " + std::to_string(p.size()) + " particles (expected N + 1)");
  }
  const std::size_t n = start.size() - 1;
  if (start[0] != 0 || start[n] != partner.size()) bad("row starts do not span the " + std::to_string(partner.size()) + " entries");
  if (history.size() != partner.size()) bad("contact histories and entries differ in number");
  // Rows first (non-decreasing, so with the ends checked every row lies inside `partner`), then entries.
  for (std::size_t i = 0; i < n; ++i) {
    if (start[i + 1] < start[i]) bad("row starts decrease at slot " + std::to_string(i));
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
      const std::uint32_t j = partner[k];
      // No pairs of a sphere with itself or inside a body.
      if (j >= n || j == i || p.body[j] == p.body[i]) {
        bad("entry " + std::to_string(k) + " (slot " + std::to_string(i) + " with " + std::to_string(j) +
            ") is not a pair of the half list");
      }
    }
  }
  if (!(skin >= 0) || !std::isfinite(skin)) bad("skin must be finite and non-negative");
  if (!skins.empty() && skins.size() != n) {
    bad(std::to_string(skins.size()) + " per-particle skins for " + std::to_string(n) + " rows (expected one per row, or none)");
  }
  double smallest = skin;
  for (std::size_t i = 0; i < skins.size(); ++i) {
    if (!(skins[i] >= 0 && skins[i] <= skin)) {
      bad("the skin of slot " + std::to_string(i) + " is " + std::to_string(skins[i]) +
          " m; each must lie in [0, " + std::to_string(skin) + "] m (the list's largest skin)");
    }
    smallest = std::min(smallest, skins[i]);
  }
  // Every pair under its smaller slot, its history seen from there: a list keyed on slot, as build()
  // makes it, comes out as it went in (a restart continues bit for bit); one of a checkpoint written
  // before 2026-12-05, keyed on id, is re-keyed, a history negated where its pair changes owner.
  // Rows in slot order, each row's entries in the order they are met.
  start_.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) ++start_[std::min<std::size_t>(i, partner[k]) + 1];
  for (std::size_t i = 0; i < n; ++i) start_[i + 1] += start_[i];
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  partner_.resize(partner.size());
  shear_.resize(history.size());
  rolling_.resize(rolling_springs_ ? history.size() : 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
      const std::uint32_t j = partner[k];
      const bool flip = j < i;
      const std::uint32_t e = fill[flip ? j : i]++;
      partner_[e] = flip ? static_cast<std::uint32_t>(i) : j;
      shear_[e] = flip ? -history[k].shear : history[k].shear;
      if (rolling_springs_) rolling_[e] = flip ? -history[k].rolling : history[k].rolling;
    }
  skin_ = skin;
  smallest_skin_ = smallest;
  skins_.clear();
  if (smallest < skin) skins_ = std::move(skins);
  builds_ = builds;
  ++generation_;
  index_partners(n);
  // The strays' slack as the build gave it: a function of the positions at the build alone.
  bounds_ = grid_bounds(p.x_at_build, p.radius, n, skin);
  assign_stray_slack(p, n, bounds_);
}

std::size_t NeighborList::bytes() const {
  std::size_t words = cell_start_.capacity() + cell_index_.capacity() + order_.capacity() + start_.capacity() +
                      partner_.capacity() + count_.capacity() + old_start_.capacity() + old_partner_.capacity() +
                      rev_start_.capacity() + rev_entry_.capacity() + rev_position_.capacity() + rev_fill_.capacity() +
                      owner_.capacity() + rev_owner_.capacity() + reach_.capacity();
  for (const auto& t : thread_partners_) words += t.capacity();
  return words * 4 + (skins_.capacity() + slack2_.capacity()) * sizeof(double) +
         (shear_.capacity() + rolling_.capacity() + old_shear_.capacity() + old_rolling_.capacity()) * sizeof(Vec3);
}

void NeighborList::keep_rolling_springs(bool keep) {
  if (keep == rolling_springs_) return;
  rolling_springs_ = keep;
  if (keep) {  // every entry's starts at zero, and the swap buffer matches the last build's entries
    rolling_.assign(shear_.size(), Vec3{});
    old_rolling_.assign(old_shear_.size(), Vec3{});
  } else {
    std::vector<Vec3>().swap(rolling_);
    std::vector<Vec3>().swap(old_rolling_);
  }
}

std::vector<ContactHistory> NeighborList::histories() const {
  std::vector<ContactHistory> h(shear_.size());
  for (std::size_t k = 0; k < h.size(); ++k) h[k] = history(static_cast<std::uint32_t>(k));
  return h;
}

}  // namespace grainscale::dem
