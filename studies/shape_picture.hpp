#pragma once
// A picture of a particle shape: three orthographic views (top: x-y, side: x-z, end: y-z) of its
// spheres, shaded by a fixed light, at a common scale, with a 1 mm scale bar.
#include "dem/shape.hpp"
#include "studies/png_image.hpp"

namespace grainscale::studies {

/// `view_px` is the size of each square view in pixels.
Image draw_shape(const dem::Shape& shape, int view_px = 240);

}  // namespace grainscale::studies
