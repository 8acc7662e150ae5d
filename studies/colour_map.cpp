#include "studies/colour_map.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace grainscale::studies {

namespace {

struct Stop {
  double t;
  Rgb colour;
};

// Control points chosen here by eye for a monotone lightness ramp; linear in RGB between them.
constexpr Stop kSequential[] = {
    {0.00, {68, 1, 84}},    {0.15, {71, 44, 122}}, {0.30, {59, 81, 139}},  {0.45, {44, 113, 142}},
    {0.60, {33, 145, 140}}, {0.75, {53, 183, 121}}, {0.88, {144, 215, 67}}, {1.00, {250, 230, 35}},
};
constexpr Stop kDiverging[] = {
    {0.00, {33, 64, 154}}, {0.25, {103, 150, 205}}, {0.50, {245, 245, 245}}, {0.75, {230, 130, 100}}, {1.00, {165, 20, 40}},
};

template <std::size_t N>
Rgb interpolate(const Stop (&stops)[N], double t) {
  t = std::clamp(t, 0.0, 1.0);
  std::size_t k = 1;
  while (k + 1 < N && stops[k].t < t) ++k;
  const Stop& a = stops[k - 1];
  const Stop& b = stops[k];
  const double f = (t - a.t) / (b.t - a.t);
  auto mix = [f](std::uint8_t p, std::uint8_t q) { return static_cast<std::uint8_t>(std::lround(p + f * (q - p))); };
  return {mix(a.colour.r, b.colour.r), mix(a.colour.g, b.colour.g), mix(a.colour.b, b.colour.b)};
}

}  // namespace

Rgb colour_at(ColourMap map, double t) {
  if (std::isnan(t)) return kNoDataColour;
  return map == ColourMap::sequential ? interpolate(kSequential, t) : interpolate(kDiverging, t);
}

}  // namespace grainscale::studies
