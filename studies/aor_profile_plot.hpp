#pragma once
// A picture of one pile, to check a measured angle by eye: the azimuthally averaged free surface
// h(r) of the pile (studies/aor_angle.hpp), the band the angle was fitted in, and a line at the
// measured mean angle through the band.
#include <string>

#include "studies/aor_angle.hpp"
#include "studies/png_image.hpp"

namespace grainscale::studies {

Image draw_pile_profile(const AngleMeasurement& m, const std::string& title);

}  // namespace grainscale::studies
