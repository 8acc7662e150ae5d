#pragma once
// Synthetic coarse-grained fields (a `grainscale cg` fields.h5, docs/coarsegrain_layout.md) whose
// measures are known in closed form, for the closure-vs-DEM tests: the default study's box
// (0.3 x 0.03 x 0.1 m, 30 x nz cells in x, z) with grain below a given (or planar) surface moving uniformly.
#include <cmath>
#include <string>
#include <vector>

#include "coarsegrain/field_file.hpp"

namespace grainscale::testing {

/// Frames at `times` of a 0.3 x 0.03 x 0.1 m box on a 30 x nz (x, z) grid: grain (density 800) below
/// the column heights heights[frame][i] (30 per frame), every grain cell moving at u_x = speeds[frame].
inline void write_bed_fields(const std::string& path, const std::vector<double>& times,
                             const std::vector<std::vector<double>>& heights, const std::vector<double>& speeds, int nz = 10) {
  const cg::Grid g = cg::Grid::make(2, {0, 0, 0}, {0.3, 0.03, 0.1}, {30, 1, nz});
  std::vector<cg::FieldFrame> frames;
  for (std::size_t j = 0; j < times.size(); ++j) {
    cg::FieldFrame fr;
    cg::Fields& f = fr.fields;
    f.grid = g;
    f.time = times[j];
    f.snapshots = 1;
    const std::size_t n = g.size();
    f.mixture.density.assign(n, 0.0);
    f.mixture.volume_fraction.assign(n, 0.0);
    f.mixture.number_density.assign(n, 0.0);
    f.mixture.temperature.assign(n, 0.0);
    f.mixture.velocity.assign(n, dem::Vec3{NAN, NAN, NAN});
    f.chaff_volume_concentration.assign(n, 0.0);
    f.chaff_number_concentration.assign(n, 0.0);
    f.chaff_mass_concentration.assign(n, 0.0);
    f.velocity_gradient.assign(n, {});
    f.shear_rate.assign(n, 0.0);
    f.chaff_velocity.assign(n, dem::Vec3{0, 0, 0});
    f.segregation_flux.assign(n, dem::Vec3{0, 0, 0});
    f.surface_height.assign(30, 0.0);
    for (int i = 0; i < 30; ++i) {
      const double h = heights[j][i];
      f.surface_height[i] = h;
      for (int k = 0; k < nz; ++k) {
        if (g.centre(2, k) > h) continue;
        const std::size_t c = g.index(i, 0, k);
        f.mixture.density[c] = 800, f.mixture.volume_fraction[c] = 0.6;
        f.mixture.velocity[c] = {speeds[j], 0, 0};
      }
    }
    frames.push_back(fr);
  }
  cg::FieldFileInfo info;
  info.container_wall = "box";
  cg::write_field_file(path, frames, info);
}

/// Frames at `times` of a 0.3 x 0.03 x 0.1 m box on a 30 x 10 grid: grain (density 800) below
/// h(x) = h0 + s (x − 0.15), moving at u_x = U.
inline void write_planar_bed_fields(const std::string& path, const std::vector<double>& times, double h0, double s, double U) {
  const cg::Grid g = cg::Grid::make(2, {0, 0, 0}, {0.3, 0.03, 0.1}, {30, 1, 10});
  std::vector<double> h(30);
  for (int i = 0; i < 30; ++i) h[i] = h0 + s * (g.centre(0, i) - 0.15);
  write_bed_fields(path, times, std::vector<std::vector<double>>(times.size(), h), std::vector<double>(times.size(), U));
}

}  // namespace grainscale::testing
