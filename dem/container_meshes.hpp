#pragma once
// Containers generated as triangle meshes, so no CAD tool is needed: the report's box (open or
// closed, optionally split into compartments), the angle-of-repose rig's pipe and tray, cylinders.
// Curved surfaces are regular polygons of `segments` sides (inscribed); a flat floor or side is one
// planar patch however it is triangulated (dem/walls/mesh.hpp).
#include <array>

#include "dem/triangle_mesh.hpp"

namespace grainscale::dem {

/// Inside surface of the box [lo, hi]; faces -x, +x, -y, +y, -z, +z each present unless open.
/// `compartments` > 1 adds full-height divider plates across the length (x) at equal spacing.
TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi, std::array<bool, 6> closed, int compartments = 1);

/// Open pipe of `radius` along z from z = 0 to `length`, centred on the z axis.
TriangleMesh pipe_mesh(double radius, double length, int segments);

/// Circular tray: a disc of `radius` at z = 0 with a rim of height `rim_height` around it.
TriangleMesh tray_mesh(double radius, double rim_height, int segments);

/// Cylinder wall of `radius` from z = 0 to `height`, with optional bottom and top discs.
TriangleMesh cylinder_mesh(double radius, double height, int segments, bool bottom, bool top);

}  // namespace grainscale::dem
