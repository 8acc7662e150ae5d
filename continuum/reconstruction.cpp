#include "continuum/reconstruction.hpp"

#include <algorithm>
#include <cmath>

#include "continuum/face_coefficients.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

const std::vector<std::string>& limiter_names() {
  static const std::vector<std::string> names{"first_order", "minmod", "van_leer", "mc", "unlimited"};
  return names;
}

Limiter limiter_from_name(const std::string& name) {
  const auto& n = limiter_names();
  for (std::size_t i = 0; i < n.size(); ++i) {
    if (n[i] == name) return static_cast<Limiter>(i);
  }
  std::string list;
  for (const auto& s : n) list += (list.empty() ? "" : ", ") + s;
  throw InputError("unknown limiter '" + name + "'; choose one of: " + list);
}

double limited_slope(Limiter limiter, double a, double b) {
  switch (limiter) {
    case Limiter::first_order:
      return 0;
    case Limiter::unlimited:
      return 0.5 * (a + b);
    default:
      break;
  }
  if (a * b <= 0) return 0;  // local extremum: no slope, so no new extremum is created
  const double s = a > 0 ? 1.0 : -1.0;
  switch (limiter) {
    case Limiter::minmod:
      return s * std::min(std::abs(a), std::abs(b));
    case Limiter::van_leer:
      return 2 * a * b / (a + b);
    case Limiter::mc:
      return s * std::min({2 * std::abs(a), 2 * std::abs(b), 0.5 * std::abs(a + b)});
    default:
      return 0;
  }
}

/// Slope of a cell with one neighbour (next to a wall, the floor or the surface), from the one-sided
/// difference b towards that neighbour. The face state c + b/2 is the mean of the two cells, so it
/// is bounded; the state on the closed side carries no flux but enters the positivity argument of
/// the update (c = ½(c⁻ + c⁺) as a convex combination), so the slope is limited to keep it in [0, 1].
/// A zero slope here would cost an O(dx) flux error in every boundary cell (L2 order 1.5).
double boundary_slope(Limiter limiter, double c, double b) {
  switch (limiter) {
    case Limiter::first_order:
      return 0;
    case Limiter::unlimited:
      return b;
    default:
      return b > 0 ? std::min(b, 2 * c) : std::max(b, -2 * (1 - c));
  }
}

void reconstruct(const Grid& g, std::span<const double> c, Limiter limiter, FaceStates& out) {
  const int nx = g.nx(), nz = g.nz();
  out.x_left.assign(x_face_count(g), 0.0);
  out.x_right.assign(x_face_count(g), 0.0);
  out.s_below.assign(s_face_count(g), 0.0);
  out.s_above.assign(s_face_count(g), 0.0);
  auto at = [&](int i, int k) { return c[g.index(i, k)]; };

  // Along layers (x-faces); the boundary slopes point towards the cell's one neighbour.
  for (int k = 0; k < nz; ++k) {
    for (int i = 0; i < nx; ++i) {
      double slope = 0;
      if (nx == 1) {
        slope = 0;
      } else if (i == 0) {
        slope = boundary_slope(limiter, at(i, k), at(i + 1, k) - at(i, k));
      } else if (i == nx - 1) {
        slope = -boundary_slope(limiter, at(i, k), at(i - 1, k) - at(i, k));
      } else {
        slope = limited_slope(limiter, at(i, k) - at(i - 1, k), at(i + 1, k) - at(i, k));
      }
      out.x_left[x_face(g, i + 1, k)] = at(i, k) + 0.5 * slope;  // left state of the face on its right
      out.x_right[x_face(g, i, k)] = at(i, k) - 0.5 * slope;     // right state of the face on its left
    }
  }
  // Along columns (σ-faces).
  for (int i = 0; i < nx; ++i) {
    for (int k = 0; k < nz; ++k) {
      double slope = 0;
      if (nz == 1) {
        slope = 0;
      } else if (k == 0) {
        slope = boundary_slope(limiter, at(i, k), at(i, k + 1) - at(i, k));
      } else if (k == nz - 1) {
        slope = -boundary_slope(limiter, at(i, k), at(i, k - 1) - at(i, k));
      } else {
        slope = limited_slope(limiter, at(i, k) - at(i, k - 1), at(i, k + 1) - at(i, k));
      }
      out.s_below[s_face(g, i, k + 1)] = at(i, k) + 0.5 * slope;
      out.s_above[s_face(g, i, k)] = at(i, k) - 0.5 * slope;
    }
  }
}

}  // namespace grainscale::continuum
