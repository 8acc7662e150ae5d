#pragma once
// A triangle-mesh wall (STL files and generated containers). Contact with a sphere goes through
// the closest feature of each nearby triangle (face interior, edge or vertex; Ericson, "Real-Time
// Collision Detection", 2005, Sec. 5.1.5), with the rules that make a mesh act like the surface it
// represents rather than like a pile of separate triangles:
//
//  * Coplanar neighbouring triangles form one planar patch: its interior edges and vertices are not
//    features, and the whole patch is one contact feature with one tangential history, so a flat
//    floor made of triangles gives exactly the force of an analytic plane, also while a sphere rolls
//    across the triangles' shared edges and vertices.
//  * An edge contact counts only if neither face next to it is touched, and a vertex contact only if
//    no face or edge around it is (face > edge > vertex; Hu et al. 2013, Powder Technol. 246:19, or
//    Su et al. 2011, "Contact detection between a sphere and triangular meshes"): a sphere on a face
//    near an edge is pushed once, by the face; a sphere over a convex rim is pushed by the rim.
//  * In a concave corner (floor meeting side wall) both faces push, as they should.
//
// Distances are unsigned: a triangle pushes spheres off either side (a thin divider plate works).
// Triangles are binned on a uniform grid in the mesh frame, each into every cell that comes within
// reach_ = 2 cells of it: a query of at most that reach (a sphere's radius, the common case) looks in
// its own cell only; a longer one visits the cells within its reach. Neighbouring cells mostly hold
// the same triangles (a container's floor spans thousands of cells), so each distinct list is stored
// once and a cell holds only a 4-byte record: its list's number and the distance below. A query then
// reads one scattered line (the record) instead of three (distance, bin start, bin contents): in the
// platform box those three loads were half of this function's time (docs/performance.md).
// Most queries come from particles far from every triangle (the inside of a bed): each cell also
// stores how many cells away the nearest occupied cell is (a Chebyshev distance transform), and a
// query whose cell is farther than its reach returns at once. That bound is safe: a triangle at
// distance D from p lies in a cell at most floor(D / cell) + 1 cells from p's (every cell holding a
// point of a triangle has it binned), so D >= (cells - 1) * cell.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dem/triangle_mesh.hpp"
#include "dem/wall.hpp"

namespace grainscale::dem {

class MeshGeometry final : public WallGeometry {
 public:
  /// `cell_size` of the triangle bins; 0 = automatic (1/128 of the largest extent).
  explicit MeshGeometry(TriangleMesh mesh, double cell_size = 0, std::string label = "mesh");

  int nearby(const Vec3& p, double reach, WallHit* hits, int cap) const override;
  /// The hint holds the sphere's cell and that cell's record: a sphere that stays in its cell (most
  /// steps: cells are millimetres, a step moves a sphere micrometres) reads its record from the hint,
  /// which the caller streams in slot order, instead of from the grid.
  bool uses_hints() const override { return true; }
  int nearby(const Vec3& p, double reach, WallHit* hits, int cap, Hint& hint) const override;
  void bounds(Vec3& lo, Vec3& hi) const override;
  std::string describe() const override;
  /// A sphere moving between features of one mesh keeps its tangential history.
  bool continues(int, int) const override { return true; }

  const TriangleMesh& mesh() const { return mesh_; }
  std::size_t patches() const { return patch_count_; }
  std::size_t edges() const { return edge_vertices_.size(); }
  /// How many cells the grid has.
  std::size_t cells() const { return cell_record_.size(); }
  /// Distinct triangle lists among the grid's cells, the empty one included.
  std::size_t bin_lists() const { return list_start_.size() - 1; }

 private:
  void build_topology();
  void build_bins(double cell_size);
  int query(const Vec3& p, double reach, WallHit* hits, int cap, Hint* hint) const;
  /// Cell (i, j, k)'s index in cell_record_.
  std::size_t cell_index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * dims_[1] + j) * dims_[2] + k;
  }

  TriangleMesh mesh_;
  std::string label_;
  std::vector<Vec3> normal_;                              // per triangle, unit
  std::vector<std::array<std::uint32_t, 3>> tri_edges_;   // per triangle: edges ab, bc, ca
  std::vector<std::array<std::uint32_t, 2>> edge_vertices_;
  std::vector<std::uint32_t> patch_;                      // per triangle: planar patch id
  std::size_t patch_count_ = 0;
  std::vector<std::uint8_t> edge_flat_, vertex_flat_;     // inside one patch: not a feature
  std::vector<std::uint32_t> edge_tri_start_, edge_tri_;  // CSR: triangles of each edge
  std::vector<std::uint32_t> vert_tri_start_, vert_tri_;  // CSR: triangles around each vertex
  std::vector<std::uint32_t> vert_edge_start_, vert_edge_;  // CSR: edges at each vertex
  // Bins: cell c = (i dims_[1] + j) dims_[2] + k has the record cell_record_[c] = list << 8 | d, where
  // d is the Chebyshev distance in cells to the nearest occupied cell (max 255) and the cell holds the
  // triangles list_tri_[list_start_[list] .. list_start_[list + 1]); list 0 is the empty one.
  Vec3 lo_, hi_, origin_;
  double cell_ = 1;
  double reach_ = 0;  // bins hold every triangle within this distance of the cell (2 cells)
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::uint32_t> cell_record_;
  std::vector<std::uint32_t> list_start_, list_tri_;
};

}  // namespace grainscale::dem
