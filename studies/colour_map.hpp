#pragma once
// Colour maps for heat maps. `sequential` is a viridis-like ramp (dark blue-violet -> teal ->
// yellow): lightness rises monotonically, so it reads correctly in grey and for the common forms of
// colour blindness. `diverging` (blue -> near-white -> red) is for signed quantities such as
// residuals, with zero at its light centre.
#include "studies/png_image.hpp"

namespace grainscale::studies {

enum class ColourMap { sequential, diverging };

/// Colour at t in [0, 1] (clamped; NaN gives the no-data grey).
Rgb colour_at(ColourMap map, double t);

/// Cells without data.
constexpr Rgb kNoDataColour{215, 215, 215};

}  // namespace grainscale::studies
