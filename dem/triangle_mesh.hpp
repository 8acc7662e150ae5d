#pragma once
// A triangle mesh: shared vertices and triangles indexing them. Read from STL (ASCII or binary) or
// generated (dem/container_meshes.hpp). STL stores every triangle's corners separately; load_stl
// welds corners that coincide (within 1e-9 of the mesh size) so that neighbouring triangles share
// vertices and edges, which the contact search needs to avoid counting a shared edge twice.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dem/vec3.hpp"

namespace grainscale::dem {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  /// Append a triangle by its corners (welded with existing vertices only by weld()).
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c);
  /// Append a planar quadrilateral a-b-c-d as two triangles.
  void add_quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
  void append(const TriangleMesh& other);
  /// Merge vertices closer than `tolerance` and drop degenerate (zero-area) triangles.
  void weld(double tolerance);
  void bounds(Vec3& lo, Vec3& hi) const;
};

/// Read an STL file, ASCII ("solid ... facet normal ... outer loop ... vertex x y z") or binary
/// (80-byte header, uint32 count, 50 bytes per triangle), scale coordinates by `scale` (e.g. 0.001
/// for a CAD file in mm) and weld shared corners. Throws InputError naming the file (and the line
/// for ASCII) on anything malformed: truncated, non-numeric, non-finite or no triangles.
TriangleMesh load_stl(const std::string& path, double scale = 1.0);

/// Write a binary STL (for looking at generated containers in ParaView or a CAD tool).
void write_stl(const TriangleMesh& mesh, const std::string& path);

}  // namespace grainscale::dem
