#pragma once
// Mass properties of a rigid union of overlapping spheres (a clump): volume, centroid, inertia tensor
// and principal frame, with overlaps counted once.
//
// Method: a regular n x n grid of columns over the clump's footprint in x-y; in each column the sphere
// chords [z_c - h, z_c + h], h = sqrt(r^2 - dx^2 - dy^2), are merged into disjoint intervals and
// integral 1, z, z^2 dz is taken exactly. Only the 2-D midpoint rule over the footprint is approximate
// (its error comes from the silhouette edges). Measured on two unequal overlapping spheres: relative
// volume error 5.6e-4 at n = 32 and 2.5e-4 at n = 64; at the default n = 256 analytic volumes and
// inertias are matched to 1e-4 (tests/dem/test_mass_properties.cpp).
#include "dem/eigen_dense.hpp"
#include <vector>

#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

struct SphereComponent {
  Vec3 center;
  double radius = 0;
};

struct MassProperties {
  double volume = 0;                 // m^3
  Vec3 centroid;                     // in the input frame
  Eigen::Matrix3d inertia_per_density;  // about the centroid, input-frame axes, m^5 (x density = kg m^2)
  Vec3 principal_moments;            // eigenvalues of inertia_per_density, ascending
  Quat principal_orientation;        // principal frame -> input frame (columns = principal axes)
};

/// Integrate over the union of `spheres` on an n x n column grid.
MassProperties union_mass_properties(const std::vector<SphereComponent>& spheres, int n = 256);

}  // namespace grainscale::dem
