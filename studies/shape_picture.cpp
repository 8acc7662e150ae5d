#include "studies/shape_picture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grainscale::studies {

namespace {

/// One view: looking along -`depth` with `right` and `up` as screen axes (unit vectors).
Image view(const dem::Shape& s, const dem::Vec3& right, const dem::Vec3& up, const dem::Vec3& depth, double centre_r,
           double centre_u, double metres_per_px, int px, Rgb colour) {
  Image img(px, px);
  const dem::Vec3 light = (1.0 / std::sqrt(3.0)) * dem::Vec3{-1, 1, 1};  // upper left, towards the viewer
  std::vector<double> zbuf(static_cast<std::size_t>(px) * px, -std::numeric_limits<double>::infinity());
  for (const auto& sp : s.spheres) {
    const double cr = dot(sp.center, right) - centre_r, cu = dot(sp.center, up) - centre_u, cd = dot(sp.center, depth);
    const int x0 = std::max(0, static_cast<int>((cr - sp.radius) / metres_per_px + px / 2));
    const int x1 = std::min(px - 1, static_cast<int>((cr + sp.radius) / metres_per_px + px / 2) + 1);
    const int y0 = std::max(0, static_cast<int>(px / 2 - (cu + sp.radius) / metres_per_px));
    const int y1 = std::min(px - 1, static_cast<int>(px / 2 - (cu - sp.radius) / metres_per_px) + 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double dr = (x + 0.5 - px / 2) * metres_per_px - cr;
        const double du = (px / 2 - y - 0.5) * metres_per_px - cu;
        const double h2 = sp.radius * sp.radius - dr * dr - du * du;
        if (h2 <= 0) continue;
        const double dd = std::sqrt(h2);
        double& z = zbuf[static_cast<std::size_t>(y) * px + x];
        if (cd + dd <= z) continue;
        z = cd + dd;
        const double shade = std::max(0.0, (dr * light.x + du * light.y + dd * light.z) / sp.radius);
        const double f = 0.35 + 0.65 * shade;
        img.at(x, y) = {static_cast<std::uint8_t>(colour.r * f), static_cast<std::uint8_t>(colour.g * f),
                        static_cast<std::uint8_t>(colour.b * f)};
      }
  }
  // 1 mm scale bar, bottom left.
  const int bar = static_cast<int>(std::lround(1e-3 / metres_per_px));
  for (int x = 8; x < 8 + bar && x < px; ++x)
    for (int y = px - 12; y < px - 9; ++y) img.at(x, y) = {0, 0, 0};
  return img;
}

}  // namespace

Image draw_shape(const dem::Shape& s, int px) {
  dem::Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& sp : s.spheres) {
    lo = {std::min(lo.x, sp.center.x - sp.radius), std::min(lo.y, sp.center.y - sp.radius), std::min(lo.z, sp.center.z - sp.radius)};
    hi = {std::max(hi.x, sp.center.x + sp.radius), std::max(hi.y, sp.center.y + sp.radius), std::max(hi.z, sp.center.z + sp.radius)};
  }
  const dem::Vec3 c = 0.5 * (lo + hi);
  const dem::Vec3 size = hi - lo;
  const double extent = std::max({size.x, size.y, size.z});
  const double mpp = 1.15 * extent / px;  // a margin around the largest extent
  const Rgb grain{214, 170, 92};
  Image out(3 * px + 20, px, {255, 255, 255});
  out.paste(view(s, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, c.x, c.y, mpp, px, grain), 0, 0);        // top
  out.paste(view(s, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, c.x, c.z, mpp, px, grain), px + 10, 0);  // side
  out.paste(view(s, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, c.y, c.z, mpp, px, grain), 2 * px + 20, 0);  // end
  return out;
}

}  // namespace grainscale::studies
