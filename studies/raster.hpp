#pragma once
// Drawing primitives on an Image for the plots: rectangles, thick and dashed lines clipped to a
// box, and point markers. Integer pixel arithmetic throughout (no anti-aliasing), so a figure's
// bytes depend only on its data.
#include "studies/png_image.hpp"

namespace grainscale::studies {

/// Inclusive pixel bounds.
struct PixelBox {
  int left = 0, top = 0, right = 0, bottom = 0;
  bool contains(int x, int y) const { return x >= left && x <= right && y >= top && y <= bottom; }
};

enum class Marker { none, circle, square, triangle, diamond, cross };

/// Filled rectangle [x0, x1] x [y0, y1] (inclusive, any corner order), clipped to `clip` and the image.
void fill_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour, const PixelBox& clip);
/// One-pixel outline of the same rectangle.
void stroke_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour, const PixelBox& clip);

/// A line between pixel positions (x0, y0) and (x1, y1) (any doubles: far-away ends are clipped to
/// `clip` before rasterising), `width` pixels thick (a square brush), dashed if asked.
void draw_line(Image& image, double x0, double y0, double x1, double y1, Rgb colour, int width, bool dashed,
               const PixelBox& clip);

/// A marker centred on pixel (x, y), about 2 * radius + 1 pixels across.
void draw_marker(Image& image, Marker marker, int x, int y, int radius, Rgb colour, const PixelBox& clip);

}  // namespace grainscale::studies
