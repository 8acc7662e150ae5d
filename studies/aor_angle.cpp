#include "studies/aor_angle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace grainscale::studies {

namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Points (r, h) of one profile: height-map cells by their distance from the axis, or silhouette
/// columns by their distance from the centre line.
struct Profile {
  std::vector<double> r, h;
};

/// Ring medians of a profile, rings of width `w` from r = 0 up to `outer`.
struct Rings {
  double w = 0;
  std::vector<double> median;  // NaN where a ring is empty
};

Rings ring_medians(const Profile& p, double w, double outer) {
  const int n = std::max(1, static_cast<int>(std::floor(outer / w)));
  std::vector<std::vector<double>> bins(n);
  for (std::size_t i = 0; i < p.r.size(); ++i) {
    const int k = static_cast<int>(p.r[i] / w);
    if (k >= 0 && k < n) bins[k].push_back(p.h[i]);
  }
  Rings out{w, {}};
  for (auto& b : bins) out.median.push_back(median(std::move(b)));
  return out;
}

/// The top (highest ring median) and base (outermost non-empty ring) of a profile.
std::pair<double, double> top_and_base(const Rings& rings) {
  double top = kNone, base = std::numeric_limits<double>::quiet_NaN();
  for (double m : rings.median) {
    if (std::isnan(m)) continue;
    top = std::max(top, m);
    base = m;
  }
  return {top, base};
}

/// Where the ring medians, going outwards from the highest ring, first fall to `level`; linear
/// interpolation between ring centres. NaN if they never do.
double crossing(const Rings& rings, double level) {
  int k_top = -1;
  double best = kNone;
  for (int k = 0; k < static_cast<int>(rings.median.size()); ++k) {
    if (!std::isnan(rings.median[k]) && rings.median[k] > best) best = rings.median[k], k_top = k;
  }
  if (k_top < 0) return std::numeric_limits<double>::quiet_NaN();
  double r_prev = (k_top + 0.5) * rings.w, h_prev = best;
  for (int k = k_top + 1; k < static_cast<int>(rings.median.size()); ++k) {
    const double h = rings.median[k];
    if (std::isnan(h)) continue;
    const double r = (k + 0.5) * rings.w;
    if (h <= level) return r_prev + (r - r_prev) * (h_prev - level) / (h_prev - h);
    r_prev = r, h_prev = h;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

/// Least-squares slope of h against r over points with r in [r0, r1]; the angle atan(-slope) in
/// degrees, NaN with fewer than `min_points` points.
double fitted_angle(const Profile& p, double r0, double r1, int min_points) {
  double n = 0, sr = 0, sh = 0, srr = 0, srh = 0;
  for (std::size_t i = 0; i < p.r.size(); ++i) {
    if (p.r[i] < r0 || p.r[i] > r1) continue;
    n += 1, sr += p.r[i], sh += p.h[i], srr += p.r[i] * p.r[i], srh += p.r[i] * p.h[i];
  }
  if (n < min_points) return std::numeric_limits<double>::quiet_NaN();
  const double slope = (n * srh - sr * sh) / (n * srr - sr * sr);
  return std::atan(-slope) * 180 / std::numbers::pi;
}

std::pair<double, double> mean_and_spread(const std::vector<double>& v) {
  double n = 0, s = 0, s2 = 0;
  for (double x : v) {
    if (std::isnan(x)) continue;
    n += 1, s += x, s2 += x * x;
  }
  if (n == 0) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  const double mean = s / n;
  return {mean, n > 1 ? std::sqrt(std::max(0.0, (s2 - n * mean * mean) / (n - 1))) : 0.0};
}

}  // namespace

AngleMeasurement measure_angle(const std::vector<dem::Vec3>& centres, const std::vector<double>& radii,
                               const AngleSettings& st) {
  if (centres.size() != radii.size()) throw std::invalid_argument("measure_angle: centres and radii differ in length");
  if (!(st.outer_radius > 0) || st.sectors < 1 || st.side_views < 1 ||
      !(st.band_low >= 0 && st.band_low < st.band_high && st.band_high <= 1)) {
    throw std::invalid_argument("measure_angle: outer radius > 0, sectors >= 1, views >= 1, 0 <= band_low < band_high <= 1");
  }
  const double R = st.outer_radius;
  // The spheres of the pile: centres over the tray.
  std::vector<std::size_t> pile;
  std::vector<double> pile_radii;
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const double dx = centres[i].x - st.axis_x, dy = centres[i].y - st.axis_y;
    if (dx * dx + dy * dy <= R * R) pile.push_back(i), pile_radii.push_back(radii[i]);
  }
  if (pile.empty()) throw std::invalid_argument("measure_angle: no sphere lies within the outer radius");
  AngleMeasurement out;
  out.spheres = static_cast<int>(pile.size());
  const double r_med = median(pile_radii);
  double cell = st.cell > 0 ? st.cell : 0.25 * r_med;
  cell = std::max(cell, 2 * R / 2000);  // at most 2000 x 2000 cells
  const int n = static_cast<int>(std::ceil(2 * R / cell));
  // Rings for locating the band: about one sphere radius wide, and at least a few cells.
  const double ring = std::max(r_med, 3 * cell);

  // --- 1. Height map and per-sector surface fit -------------------------------------------------
  std::vector<double> top(static_cast<std::size_t>(n) * n, kNone);
  const double x0 = st.axis_x - R, y0 = st.axis_y - R;
  for (std::size_t i : pile) {
    const dem::Vec3& c = centres[i];
    const double r = radii[i];
    const int ix0 = std::max(0, static_cast<int>(std::floor((c.x - r - x0) / cell)));
    const int ix1 = std::min(n - 1, static_cast<int>(std::floor((c.x + r - x0) / cell)));
    const int iy0 = std::max(0, static_cast<int>(std::floor((c.y - r - y0) / cell)));
    const int iy1 = std::min(n - 1, static_cast<int>(std::floor((c.y + r - y0) / cell)));
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix) {
        const double dx = x0 + (ix + 0.5) * cell - c.x, dy = y0 + (iy + 0.5) * cell - c.y;
        const double h2 = r * r - dx * dx - dy * dy;
        if (h2 < 0) continue;
        double& t = top[static_cast<std::size_t>(iy) * n + ix];
        t = std::max(t, c.z + std::sqrt(h2));
      }
  }
  Profile all;
  std::vector<Profile> sector(st.sectors);
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) {
      const double h = top[static_cast<std::size_t>(iy) * n + ix];
      if (h == kNone) continue;  // no sphere above this cell
      const double dx = x0 + (ix + 0.5) * cell - st.axis_x, dy = y0 + (iy + 0.5) * cell - st.axis_y;
      const double rho = std::sqrt(dx * dx + dy * dy);
      if (rho > R) continue;
      all.r.push_back(rho), all.h.push_back(h);
      const double phi = std::atan2(dy, dx) + std::numbers::pi;  // [0, 2 pi]
      const int s = std::min(st.sectors - 1, static_cast<int>(phi / (2 * std::numbers::pi) * st.sectors));
      sector[s].r.push_back(rho), sector[s].h.push_back(h);
    }
  const Rings rings = ring_medians(all, ring, R);
  for (std::size_t k = 0; k < rings.median.size(); ++k) {
    if (!std::isnan(rings.median[k])) out.profile_r.push_back((k + 0.5) * ring), out.profile_h.push_back(rings.median[k]);
  }
  std::tie(out.top_height, out.base_height) = top_and_base(rings);
  const double H = out.top_height - out.base_height;
  if (!(H > r_med)) {
    throw std::invalid_argument("measure_angle: the surface rises less than a sphere radius above its base: no pile");
  }
  out.fit_r_inner = crossing(rings, out.base_height + st.band_high * H);
  out.fit_r_outer = crossing(rings, out.base_height + st.band_low * H);
  if (std::isnan(out.fit_r_inner) || std::isnan(out.fit_r_outer) || !(out.fit_r_outer > out.fit_r_inner)) {
    throw std::invalid_argument("measure_angle: the averaged surface profile does not fall through the fitted band");
  }
  for (const Profile& p : sector) out.sector_deg.push_back(fitted_angle(p, out.fit_r_inner, out.fit_r_outer, 10));
  std::tie(out.mean_deg, out.spread_deg) = mean_and_spread(out.sector_deg);

  // --- 2. Side projections (silhouettes), two flanks each ---------------------------------------
  for (int v = 0; v < st.side_views; ++v) {
    const double phi = v * std::numbers::pi / st.side_views;
    const double ux = std::cos(phi), uy = std::sin(phi);
    std::vector<double> sil(static_cast<std::size_t>(n), kNone);  // columns over u in [-R, R]
    for (std::size_t i : pile) {
      const double u = (centres[i].x - st.axis_x) * ux + (centres[i].y - st.axis_y) * uy;
      const double r = radii[i];
      const int k0 = std::max(0, static_cast<int>(std::floor((u - r + R) / cell)));
      const int k1 = std::min(n - 1, static_cast<int>(std::floor((u + r + R) / cell)));
      for (int k = k0; k <= k1; ++k) {
        const double du = -R + (k + 0.5) * cell - u, h2 = r * r - du * du;
        if (h2 >= 0) sil[k] = std::max(sil[k], centres[i].z + std::sqrt(h2));
      }
    }
    for (int side = 0; side < 2; ++side) {  // left flank (u < 0), right flank (u > 0)
      Profile flank;
      for (int k = 0; k < n; ++k) {
        const double u = -R + (k + 0.5) * cell;
        if (sil[k] == kNone || (side == 0 ? u > 0 : u < 0)) continue;
        flank.r.push_back(std::abs(u)), flank.h.push_back(sil[k]);
      }
      const Rings fr = ring_medians(flank, ring, R);
      const auto [ftop, fbase] = top_and_base(fr);
      const double fh = ftop - fbase;
      double angle = std::numeric_limits<double>::quiet_NaN();
      if (fh > 0) {
        const double a = crossing(fr, fbase + st.band_high * fh), b = crossing(fr, fbase + st.band_low * fh);
        if (b > a) angle = fitted_angle(flank, a, b, 4);
      }
      out.side_deg.push_back(angle);
    }
  }
  std::tie(out.side_mean_deg, out.side_spread_deg) = mean_and_spread(out.side_deg);
  return out;
}

}  // namespace grainscale::studies
