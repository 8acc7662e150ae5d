#pragma once
// Top-view surface coverage: what the physical test measured from photographs taken above the
// container ("the number of pixels that contained chaff over the length of the container": about
// 10 % in the centre and 60 % at the ends for wheat after 30 min; SAGIT USA120 report).
//
// The spheres are rendered onto a pixel grid over the container's floor (x, y), looking down -z in
// the container frame: a pixel is covered by a sphere if the pixel's centre lies inside the sphere's
// projected disc, and the sphere's surface there is at z_p + sqrt(r^2 - d^2) (a z-buffer). A pixel is
// chaff if a chaff sphere covering it reaches within `layer_thickness` of the pixel's top surface;
// with thickness 0 that is exactly the sphere a camera would see (ties count as chaff). Coverage is
// chaff pixels over occupied pixels (pixels that see any particle), so bare floor does not dilute it;
// the fraction of occupied pixels is reported beside it.
#include <cstdint>
#include <vector>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/slices.hpp"

namespace grainscale::cg {

struct TopViewSettings {
  double pixel = 0.001;         // pixel edge, m (true size: photographs do not scale with the DEM)
  double layer_thickness = 0;   // m; 0: the visible top only
};

struct TopView {
  enum Pixel : std::uint8_t { empty = 0, grain = 1, chaff = 2 };
  double x_lo = 0, y_lo = 0, pixel = 0;
  int nx = 0, ny = 0;
  std::vector<double> height;        // top surface z per pixel (-inf where empty); index i + nx j
  std::vector<std::uint8_t> state;   // Pixel per pixel

  double x(int i) const { return x_lo + (i + 0.5) * pixel; }
  /// Chaff pixels / occupied pixels (NaN if none is occupied).
  double coverage() const;
  /// Occupied pixels / all pixels.
  double occupied_fraction() const;
};

/// Render the particles over the rectangle [lo.x, hi.x] x [lo.y, hi.y] of the container floor.
TopView render_top_view(const CgParticles& particles, const SpeciesTable& species, const dem::Vec3& lo, const dem::Vec3& hi,
                        const TopViewSettings& settings);

/// Coverage per slice along x: chaff pixels / occupied pixels of the pixel columns whose centre lies
/// in the slice (NaN for a slice without occupied pixels).
struct CoverageProfile {
  Slices slices;
  std::vector<double> coverage;
  std::vector<long> occupied_pixels, chaff_pixels;
};
CoverageProfile coverage_profile(const TopView& view, const Slices& slices);

}  // namespace grainscale::cg
