#pragma once
// A particle shape: a rigid union of overlapping spheres (a clump), read from a YAML file such as
// studies/shapes/wheat.yaml:
//
//   name: wheat
//   source: "seed size 6.7 x 3.3 mm (source report, grain sample table)"
//   length_unit: mm                    # m (default) or mm
//   measured_size: [6.7, 3.3]          # length, width[, thickness]: what the bounding box must match
//   spheres:
//     - {center: [-2.5373, 0, 0], radius: 0.8127}
//     ...
//
// Users add a shape by writing such a file; `grainscale shape FILE.yaml --png FILE.png` prints its
// size and mass properties and draws it.
#include <string>
#include <vector>

#include "dem/mass_properties.hpp"

namespace grainscale::dem {

struct Shape {
  std::string name;
  std::string source;
  std::vector<SphereComponent> spheres;  // metres, in the file's frame
  std::vector<double> measured_size;     // metres: length, width[, thickness]

  /// Extent of the union along x, y and z (the file's frame), metres.
  Vec3 bounding_size() const;
  /// Bounding extents sorted descending (length >= width >= thickness), metres.
  std::vector<double> sorted_dimensions() const;
};

/// Load and validate: every sphere positive and finite, the spheres one connected rigid piece, at most
/// 1000 spheres. Errors are InputError naming file, line and key.
Shape load_shape(const std::string& file);

}  // namespace grainscale::dem
