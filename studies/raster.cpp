#include "studies/raster.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace grainscale::studies {

namespace {

void put(Image& image, int x, int y, Rgb colour, const PixelBox& clip) {
  if (clip.contains(x, y) && x >= 0 && y >= 0 && x < image.width() && y < image.height()) image.at(x, y) = colour;
}

/// Liang–Barsky: clip the segment to the box (widened by `pad` pixels); false if nothing is left.
bool clip_segment(double& x0, double& y0, double& x1, double& y1, const PixelBox& box, double pad) {
  const double dx = x1 - x0, dy = y1 - y0;
  double t0 = 0, t1 = 1;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {x0 - (box.left - pad), (box.right + pad) - x0, y0 - (box.top - pad), (box.bottom + pad) - y0};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
      continue;
    }
    const double r = q[k] / p[k];
    if (p[k] < 0) t0 = std::max(t0, r);
    else t1 = std::min(t1, r);
    if (t0 > t1) return false;
  }
  const double ax = x0 + t0 * dx, ay = y0 + t0 * dy;
  x1 = x0 + t1 * dx;
  y1 = y0 + t1 * dy;
  x0 = ax;
  y0 = ay;
  return true;
}

}  // namespace

void fill_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour, const PixelBox& clip) {
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  x0 = std::max({x0, clip.left, 0});
  y0 = std::max({y0, clip.top, 0});
  x1 = std::min({x1, clip.right, image.width() - 1});
  y1 = std::min({y1, clip.bottom, image.height() - 1});
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) image.at(x, y) = colour;
}

void stroke_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour, const PixelBox& clip) {
  fill_rect(image, x0, y0, x1, y0, colour, clip);
  fill_rect(image, x0, y1, x1, y1, colour, clip);
  fill_rect(image, x0, y0, x0, y1, colour, clip);
  fill_rect(image, x1, y0, x1, y1, colour, clip);
}

void draw_line(Image& image, double x0, double y0, double x1, double y1, Rgb colour, int width, bool dashed,
               const PixelBox& clip) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  if (!clip_segment(x0, y0, x1, y1, clip, width + 2.0)) return;
  // Bresenham between the rounded ends.
  int ax = static_cast<int>(std::lround(x0)), ay = static_cast<int>(std::lround(y0));
  const int bx = static_cast<int>(std::lround(x1)), by = static_cast<int>(std::lround(y1));
  const int dx = std::abs(bx - ax), dy = -std::abs(by - ay);
  const int sx = ax < bx ? 1 : -1, sy = ay < by ? 1 : -1;
  int err = dx + dy;
  const int lo = -(width - 1) / 2, hi = width / 2;
  constexpr int kDashOn = 9, kDashPeriod = 15;
  for (int step = 0;; ++step) {
    if (!dashed || step % kDashPeriod < kDashOn) {
      for (int oy = lo; oy <= hi; ++oy)
        for (int ox = lo; ox <= hi; ++ox) put(image, ax + ox, ay + oy, colour, clip);
    }
    if (ax == bx && ay == by) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      ax += sx;
    }
    if (e2 <= dx) {
      err += dx;
      ay += sy;
    }
  }
}

void draw_marker(Image& image, Marker marker, int x, int y, int r, Rgb colour, const PixelBox& clip) {
  for (int v = -r; v <= r; ++v)
    for (int u = -r; u <= r; ++u) {
      bool on = false;
      switch (marker) {
        case Marker::none: return;
        case Marker::circle: on = u * u + v * v <= r * r + r; break;
        case Marker::square: on = std::abs(u) < r && std::abs(v) < r; break;
        case Marker::diamond: on = std::abs(u) + std::abs(v) <= r; break;
        // Apex up: the half-width grows from 0 at the top row to r at the bottom row.
        case Marker::triangle: on = 2 * std::abs(u) <= v + r; break;
        case Marker::cross: on = std::abs(std::abs(u) - std::abs(v)) <= 0; break;
      }
      if (on) {
        put(image, x + u, y + v, colour, clip);
        if (marker == Marker::cross) put(image, x + u + 1, y + v, colour, clip);  // two pixels thick
      }
    }
}

}  // namespace grainscale::studies
