#include "dem/mass_properties.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainscale::dem {

namespace {

struct Interval {
  double a, b;
};

}  // namespace

MassProperties union_mass_properties(const std::vector<SphereComponent>& spheres, int n) {
  if (spheres.empty()) throw std::invalid_argument("union_mass_properties: no spheres");
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& s : spheres) {
    if (!(s.radius > 0)) throw std::invalid_argument("union_mass_properties: radius must be positive");
    x0 = std::min(x0, s.center.x - s.radius), x1 = std::max(x1, s.center.x + s.radius);
    y0 = std::min(y0, s.center.y - s.radius), y1 = std::max(y1, s.center.y + s.radius);
  }
  const double dx = (x1 - x0) / n, dy = (y1 - y0) / n, da = dx * dy;

  // Moments: V, S_x, S_y, S_z, S_xx, S_yy, S_zz, S_xy, S_xz, S_yz (per unit density).
  double m[10] = {};
  std::vector<Interval> iv;
  iv.reserve(spheres.size());
  for (int i = 0; i < n; ++i) {
    const double x = x0 + (i + 0.5) * dx;
    for (int j = 0; j < n; ++j) {
      const double y = y0 + (j + 0.5) * dy;
      iv.clear();
      for (const auto& s : spheres) {
        const double h2 = s.radius * s.radius - (x - s.center.x) * (x - s.center.x) - (y - s.center.y) * (y - s.center.y);
        if (h2 > 0) {
          const double h = std::sqrt(h2);
          iv.push_back({s.center.z - h, s.center.z + h});
        }
      }
      if (iv.empty()) continue;
      std::sort(iv.begin(), iv.end(), [](const Interval& p, const Interval& q) { return p.a < q.a; });
      double l0 = 0, l1 = 0, l2 = 0;  // integral of 1, z, z^2 over the union of the intervals
      double a = iv[0].a, b = iv[0].b;
      auto flush = [&] {
        l0 += b - a;
        l1 += 0.5 * (b * b - a * a);
        l2 += (b * b * b - a * a * a) / 3.0;
      };
      for (std::size_t k = 1; k < iv.size(); ++k) {
        if (iv[k].a > b) {
          flush();
          a = iv[k].a;
          b = iv[k].b;
        } else {
          b = std::max(b, iv[k].b);
        }
      }
      flush();
      m[0] += da * l0;
      m[1] += da * x * l0;
      m[2] += da * y * l0;
      m[3] += da * l1;
      m[4] += da * x * x * l0;
      m[5] += da * y * y * l0;
      m[6] += da * l2;
      m[7] += da * x * y * l0;
      m[8] += da * x * l1;
      m[9] += da * y * l1;
    }
  }

  MassProperties p;
  p.volume = m[0];
  const Eigen::Vector3d c(m[1] / m[0], m[2] / m[0], m[3] / m[0]);
  p.centroid = {c.x(), c.y(), c.z()};
  // Inertia about the origin: I_ij = integral (|r|^2 delta_ij - r_i r_j).
  Eigen::Matrix3d io;
  io << m[5] + m[6], -m[7], -m[8],  //
      -m[7], m[4] + m[6], -m[9],    //
      -m[8], -m[9], m[4] + m[5];
  // Parallel-axis theorem to the centroid.
  p.inertia_per_density = io - m[0] * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());

  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(p.inertia_per_density);
  const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) *= -1;  // right-handed principal frame
  p.principal_moments = {ev(0), ev(1), ev(2)};
  const Eigen::Quaterniond q(axes);
  p.principal_orientation = normalized({q.w(), q.x(), q.y(), q.z()});
  return p;
}

}  // namespace grainscale::dem
