#pragma once
// The angle of repose of a pile, measured from particle positions (component spheres: centres and
// radii) in two ways:
//
// 1. Free-surface fit, per azimuthal sector. The spheres' tops are rendered into a height map on a
//    horizontal grid (z-buffer: a cell holds the highest sphere surface above its centre), which
//    weights the surface by area, as a laser scan would, and needs no choice of "surface particles".
//    An azimuthally averaged profile h(r) (median per radial ring) gives the pile's top and base
//    heights; the fitted band is the range of r where that profile lies between 20 % and 80 % of the
//    pile height above its base (a common choice for AOR fits, e.g. Roessler & Katterfeld 2018, which
//    keeps the rounded top and the toe out of the fit). In each sector, h = a + b r is fitted by least
//    squares to the cells in that band; the angle is atan(-b). The band is chosen in r, not by each
//    cell's own height, because selecting points by their dependent variable biases a regression.
//    Result: mean and standard deviation over the sectors.
// 2. Side projection, like the report's image processing (a photograph of the pile from the side):
//    the silhouette of all spheres seen horizontally from several azimuths, its left and right
//    flanks fitted in the same 20-80 % band. Result: mean and spread over the flanks. A silhouette
//    holds the highest point along each line of sight, so roughness raises it a little; on a cone it
//    is the cone's meridian and gives the cone's angle.
//
// Only spheres whose centre lies within `outer_radius` of the axis (the tray) count: grain that
// overflowed onto the floor is not part of the pile.
#include <vector>

#include "dem/vec3.hpp"

namespace grainscale::studies {

struct AngleSettings {
  double axis_x = 0, axis_y = 0;  // the pile's vertical axis (the pipe's)
  double outer_radius = 0.1;      // m: the pile's base radius (the tray's)
  int sectors = 8;                // azimuthal sectors of the surface fit
  int side_views = 4;             // side projections at azimuths 0, 180/n, ... degrees (two flanks each)
  double band_low = 0.2, band_high = 0.8;  // fitted part of the pile height above its base
  double cell = 0;                // m, height-map cell; 0 = a quarter of the median sphere radius
};

struct AngleMeasurement {
  double mean_deg = 0, spread_deg = 0;  // surface fit: mean and standard deviation over sectors
  std::vector<double> sector_deg;       // per sector (NaN where a sector had too few cells)
  double side_mean_deg = 0, side_spread_deg = 0;  // side projection: over flanks
  std::vector<double> side_deg;         // per view: left flank, right flank
  double top_height = 0, base_height = 0;  // m, of the averaged profile
  double fit_r_inner = 0, fit_r_outer = 0;  // m, the fitted band
  std::vector<double> profile_r, profile_h;  // m: the azimuthally averaged surface (ring centres, medians)
  int spheres = 0;                      // spheres counted (within the outer radius)
};

/// Throws std::invalid_argument when the spheres do not form a pile (none inside the outer radius,
/// or no height difference between top and base).
AngleMeasurement measure_angle(const std::vector<dem::Vec3>& centres, const std::vector<double>& radii,
                               const AngleSettings& settings);

}  // namespace grainscale::studies
