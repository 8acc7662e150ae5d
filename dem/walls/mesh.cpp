#include "dem/walls/mesh.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

#include "dem/input_error.hpp"
#include "dem/uninitialized_array.hpp"

namespace grainscale::dem {

namespace {

enum Region { kFace, kEdgeAB, kEdgeBC, kEdgeCA, kVertexA, kVertexB, kVertexC };

struct Closest {
  Vec3 point;
  Region region;
};

/// Closest point of triangle abc to p and the Voronoi region it lies in (Ericson 2005, Sec. 5.1.5:
/// barycentric tests against the vertex, then edge, regions; otherwise the face).
Closest closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {a, kVertexA};
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {b, kVertexB};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {a + (d1 / (d1 - d3)) * ab, kEdgeAB};
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {c, kVertexC};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {a + (d2 / (d2 - d6)) * ac, kEdgeCA};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return {b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), kEdgeBC};
  }
  const double denom = 1 / (va + vb + vc);
  return {a + (vb * denom) * ab + (vc * denom) * ac, kFace};
}

/// Union-find root with path halving.
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

void build_csr(std::size_t n, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
               std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items) {
  start.assign(n + 1, 0);
  for (auto [k, v] : pairs) ++start[k + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  items.resize(pairs.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (auto [k, v] : pairs) items[fill[k]++] = v;
}

}  // namespace

MeshGeometry::MeshGeometry(TriangleMesh mesh, double cell_size, std::string label)
    : mesh_(std::move(mesh)), label_(std::move(label)) {
  if (mesh_.triangles.empty()) throw InputError(label_ + ": a mesh wall needs at least one triangle");
  build_topology();
  build_bins(cell_size);
}

void MeshGeometry::build_topology() {
  const std::size_t nt = mesh_.triangles.size(), nv = mesh_.vertices.size();
  normal_.resize(nt);
  tri_edges_.resize(nt);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge_id;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_tri, vert_tri, vert_edge;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = mesh_.triangles[t];
    const Vec3 n = cross(mesh_.vertices[v[1]] - mesh_.vertices[v[0]], mesh_.vertices[v[2]] - mesh_.vertices[v[0]]);
    normal_[t] = (1.0 / norm(n)) * n;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = v[k], b = v[(k + 1) % 3];
      const auto key = std::minmax(a, b);
      auto [it, added] = edge_id.try_emplace({key.first, key.second}, static_cast<std::uint32_t>(edge_vertices_.size()));
      if (added) {
        edge_vertices_.push_back({key.first, key.second});
        vert_edge.push_back({key.first, it->second});
        vert_edge.push_back({key.second, it->second});
      }
      tri_edges_[t][k] = it->second;
      edge_tri.push_back({it->second, static_cast<std::uint32_t>(t)});
      vert_tri.push_back({v[k], static_cast<std::uint32_t>(t)});
    }
  }
  const std::size_t ne = edge_vertices_.size();
  build_csr(ne, edge_tri, edge_tri_start_, edge_tri_);
  build_csr(nv, vert_tri, vert_tri_start_, vert_tri_);
  build_csr(nv, vert_edge, vert_edge_start_, vert_edge_);

  // Planar patches: join triangles across an edge when they lie in one plane.
  Vec3 lo, hi;
  mesh_.bounds(lo, hi);
  const double tol = 1e-9 * norm(hi - lo);
  std::vector<std::uint32_t> parent(nt);
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::size_t e = 0; e < ne; ++e) {
    for (std::uint32_t i = edge_tri_start_[e]; i < edge_tri_start_[e + 1]; ++i)
      for (std::uint32_t j = i + 1; j < edge_tri_start_[e + 1]; ++j) {
        const std::uint32_t s = edge_tri_[i], t = edge_tri_[j];
        const bool parallel = std::abs(dot(normal_[s], normal_[t])) > 1 - 1e-12;
        const auto& vt = mesh_.triangles[t];
        bool coplanar = parallel;
        for (int k = 0; k < 3 && coplanar; ++k) {
          coplanar = std::abs(dot(mesh_.vertices[vt[k]] - mesh_.vertices[mesh_.triangles[s][0]], normal_[s])) <= tol;
        }
        if (coplanar) parent[find_root(parent, s)] = find_root(parent, t);
      }
  }
  std::map<std::uint32_t, std::uint32_t> patch_of_root;
  patch_.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const std::uint32_t r = find_root(parent, static_cast<std::uint32_t>(t));
    patch_[t] = patch_of_root.try_emplace(r, static_cast<std::uint32_t>(patch_of_root.size())).first->second;
  }
  patch_count_ = patch_of_root.size();

  // An edge is flat when two or more triangles share it, all in one patch; a vertex is flat when
  // every triangle around it is in one patch and every edge at it is flat.
  edge_flat_.assign(ne, 0);
  for (std::size_t e = 0; e < ne; ++e) {
    const std::uint32_t b = edge_tri_start_[e], en = edge_tri_start_[e + 1];
    bool flat = en - b >= 2;
    for (std::uint32_t i = b; i < en && flat; ++i) flat = patch_[edge_tri_[i]] == patch_[edge_tri_[b]];
    edge_flat_[e] = flat;
  }
  vertex_flat_.assign(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    bool flat = vert_tri_start_[v + 1] > vert_tri_start_[v];
    for (std::uint32_t i = vert_tri_start_[v]; i < vert_tri_start_[v + 1] && flat; ++i) {
      flat = patch_[vert_tri_[i]] == patch_[vert_tri_[vert_tri_start_[v]]];
    }
    for (std::uint32_t i = vert_edge_start_[v]; i < vert_edge_start_[v + 1] && flat; ++i) flat = edge_flat_[vert_edge_[i]];
    vertex_flat_[v] = flat;
  }
}

void MeshGeometry::build_bins(double cell_size) {
  mesh_.bounds(lo_, hi_);
  const Vec3 ext = hi_ - lo_;
  const double largest = std::max({ext.x, ext.y, ext.z});
  cell_ = cell_size > 0 ? cell_size : largest / 128;
  // Keep the grid to a few million cells whatever the requested size. (A coarser default for meshes
  // of few triangles kept the records in the cache, but the cell size decides the order in which a
  // query that spans several cells finds its features, hence the order of a sphere's wall forces:
  // trajectories changed; docs/performance.md, "tenth session".)
  auto cells_for = [&](double h) {
    return (std::floor(ext.x / h) + 1) * (std::floor(ext.y / h) + 1) * (std::floor(ext.z / h) + 1);
  };
  while (cells_for(cell_) > 4e6) cell_ *= 1.25;
  origin_ = lo_;
  dims_ = {static_cast<int>(ext.x / cell_) + 1, static_cast<int>(ext.y / cell_) + 1, static_cast<int>(ext.z / cell_) + 1};
  const std::size_t ncell = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  // A triangle goes into every cell whose centre lies within half a cell diagonal plus `reach_`
  // of it, so every point of the cell's box within reach_ of the triangle finds it in that one cell
  // (a query with a smaller reach looks no further; header).
  reach_ = 2 * cell_;
  const double half_diag = 0.5 * std::sqrt(3.0) * cell_ * (1 + 1e-9) + reach_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cell_tri;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& v = mesh_.triangles[t];
    const Vec3 a = mesh_.vertices[v[0]], b = mesh_.vertices[v[1]], c = mesh_.vertices[v[2]];
    int lo[3], hi[3];
    const double mn[3] = {std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})};
    const double mx[3] = {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})};
    const double o[3] = {origin_.x, origin_.y, origin_.z};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::clamp(static_cast<int>(std::floor((mn[k] - reach_ - o[k]) / cell_)), 0, dims_[k] - 1);
      hi[k] = std::clamp(static_cast<int>(std::floor((mx[k] + reach_ - o[k]) / cell_)), 0, dims_[k] - 1);
    }
    for (int i = lo[0]; i <= hi[0]; ++i)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int k = lo[2]; k <= hi[2]; ++k) {
          const Vec3 centre = origin_ + Vec3{(i + 0.5) * cell_, (j + 0.5) * cell_, (k + 0.5) * cell_};
          if (norm(closest_on_triangle(centre, a, b, c).point - centre) > half_diag) continue;
          cell_tri.push_back({static_cast<std::uint32_t>(cell_index(i, j, k)), static_cast<std::uint32_t>(t)});
        }
  }
  std::vector<std::uint32_t> bin_start, bin_tri;
  build_csr(ncell, cell_tri, bin_start, bin_tri);

  // Chebyshev distance (in cells) to the nearest occupied cell: breadth-first from every occupied
  // cell over the 26 neighbours, capped at 255.
  std::vector<std::uint8_t> to_triangle(ncell, 255);
  std::vector<std::uint32_t> front, next;
  for (std::size_t c = 0; c < ncell; ++c)
    if (bin_start[c + 1] > bin_start[c]) to_triangle[c] = 0, front.push_back(static_cast<std::uint32_t>(c));
  for (int d = 1; d < 255 && !front.empty(); ++d) {
    next.clear();
    for (const std::uint32_t c : front) {
      const int i = static_cast<int>(c / (static_cast<std::size_t>(dims_[1]) * dims_[2]));
      const int j = static_cast<int>(c / dims_[2] % dims_[1]), k = static_cast<int>(c % dims_[2]);
      for (int a = std::max(i - 1, 0); a <= std::min(i + 1, dims_[0] - 1); ++a)
        for (int b = std::max(j - 1, 0); b <= std::min(j + 1, dims_[1] - 1); ++b)
          for (int e = std::max(k - 1, 0); e <= std::min(k + 1, dims_[2] - 1); ++e) {
            const std::size_t n = cell_index(a, b, e);
            if (to_triangle[n] > d) to_triangle[n] = static_cast<std::uint8_t>(d), next.push_back(static_cast<std::uint32_t>(n));
          }
    }
    front.swap(next);
  }

  // Each distinct list once (the same triangles in the same order, so a query tests them in the order
  // it did when every cell had its own copy), numbered in order of first appearance, the empty list 0.
  std::map<std::vector<std::uint32_t>, std::uint32_t> number;
  list_start_.assign(1, 0);
  list_tri_.clear();
  auto add_list = [&](std::vector<std::uint32_t> tris) {
    const auto [it, added] = number.emplace(std::move(tris), static_cast<std::uint32_t>(list_start_.size() - 1));
    if (added) {
      list_tri_.insert(list_tri_.end(), it->first.begin(), it->first.end());
      list_start_.push_back(static_cast<std::uint32_t>(list_tri_.size()));
    }
    return it->second;
  };
  add_list({});
  cell_record_.resize(ncell);
  std::uint32_t previous = 0;  // the list of cell c - 1: neighbours along k mostly share it
  for (std::size_t c = 0; c < ncell; ++c) {
    const auto first = bin_tri.begin() + bin_start[c], last = bin_tri.begin() + bin_start[c + 1];
    const auto same_first = list_tri_.begin() + list_start_[previous], same_last = list_tri_.begin() + list_start_[previous + 1];
    const std::uint32_t list = first == last                                  ? 0
                               : std::equal(first, last, same_first, same_last) ? previous
                                                                                : add_list(std::vector<std::uint32_t>(first, last));
    previous = list;
    // ncell <= ~4e6 (above), so a list number fits the record's 24 bits.
    assert(list < (1u << 24));
    cell_record_[c] = list << 8 | to_triangle[c];
  }
}

int MeshGeometry::nearby(const Vec3& p, double reach, WallHit* hits, int cap) const {
  return query(p, reach, hits, cap, nullptr);
}

int MeshGeometry::nearby(const Vec3& p, double reach, WallHit* hits, int cap, Hint& hint) const {
  return query(p, reach, hits, cap, &hint);
}

int MeshGeometry::query(const Vec3& p, double reach, WallHit* hits, int cap, Hint* hint) const {
  const double q[3] = {p.x - origin_.x, p.y - origin_.y, p.z - origin_.z};
  // Far from every triangle (header): nothing to test. Outside the grid the bound still holds for
  // the nearest grid cell, less the distance to the grid, which the cell test below handles.
  // The record of p's cell: from the hint if p is in the cell it names (hint: cell << 32 | record).
  int c3[3];
  bool inside = true;
  for (int k = 0; k < 3; ++k) {
    c3[k] = static_cast<int>(std::floor(q[k] / cell_));
    inside = inside && c3[k] >= 0 && c3[k] < dims_[k];
  }
  std::uint32_t own_record = 0;
  if (inside) {
    const std::size_t c = cell_index(c3[0], c3[1], c3[2]);
    if (hint != nullptr && *hint >> 32 == c) {
      own_record = static_cast<std::uint32_t>(*hint);
    } else {
      own_record = cell_record_[c];
      if (hint != nullptr) *hint = static_cast<Hint>(c) << 32 | own_record;
    }
    const int d = static_cast<int>(own_record & 0xffu);
    if ((d - 1) * cell_ > reach) return 0;
  }
  // Cells overlapping the query box [p - reach, p + reach]; only p's own cell if it lies in the grid
  // and reach <= reach_ (its bin holds every triangle that close).
  int lo[3], hi[3];
  const bool own_cell = inside && reach <= reach_;
  for (int k = 0; k < 3; ++k) {
    if (own_cell) {
      lo[k] = hi[k] = c3[k];
      continue;
    }
    lo[k] = static_cast<int>(std::floor((q[k] - reach) / cell_));
    hi[k] = static_cast<int>(std::floor((q[k] + reach) / cell_));
    if (hi[k] < 0 || lo[k] >= dims_[k]) return 0;
    lo[k] = std::max(lo[k], 0);
    hi[k] = std::min(hi[k], dims_[k] - 1);
  }

  enum Kind : std::uint8_t { kFaceHit, kEdgeHit, kVertexHit };
  struct Candidate {
    Kind kind;
    std::uint32_t id;  // patch, edge or vertex
    double distance;
    Vec3 normal;
  };
  constexpr int kMax = 64;
  UninitializedArray<std::uint32_t, 4 * kMax> seen;  // triangles already tested
  UninitializedArray<Candidate, kMax> cand;
  int n_seen = 0, n_cand = 0;

  auto add = [&](Kind kind, std::uint32_t id, double d, const Vec3& nrm) {
    for (int c = 0; c < n_cand; ++c)
      if (cand[c].kind == kind && cand[c].id == id) {
        if (d < cand[c].distance) cand[c].distance = d, cand[c].normal = nrm;
        return;
      }
    if (n_cand < kMax) cand[n_cand++] = {kind, id, d, nrm};
  };

  for (int i = lo[0]; i <= hi[0]; ++i)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int k = lo[2]; k <= hi[2]; ++k) {
        const std::uint32_t list = (own_cell ? own_record : cell_record_[cell_index(i, j, k)]) >> 8;
        for (std::uint32_t m = list_start_[list]; m < list_start_[list + 1]; ++m) {
          const std::uint32_t t = list_tri_[m];
          bool dup = false;
          for (int s = 0; s < n_seen && !dup; ++s) dup = seen[s] == t;
          if (dup) continue;
          if (n_seen < 4 * kMax) seen[n_seen++] = t;
          const auto& v = mesh_.triangles[t];
          // The distance to a triangle is at least that to its plane: one dot product rejects most.
          if (std::abs(dot(p - mesh_.vertices[v[0]], normal_[t])) >= reach) continue;
          const Closest cl = closest_on_triangle(p, mesh_.vertices[v[0]], mesh_.vertices[v[1]], mesh_.vertices[v[2]]);
          const Vec3 d = p - cl.point;
          const double dist = norm(d);
          if (dist >= reach) continue;
          // Face contacts (also on the flat edges and vertices inside a patch) take distance and
          // normal from the plane, which is exact to round-off like an analytic plane; edge and
          // vertex contacts from the closest point.
          const bool on_face = cl.region == kFace ||
                               (cl.region <= kEdgeCA ? edge_flat_[tri_edges_[t][cl.region - kEdgeAB]] != 0
                                                     : vertex_flat_[v[cl.region - kVertexA]] != 0);
          if (on_face) {
            const double h = dot(p - mesh_.vertices[v[0]], normal_[t]);
            add(kFaceHit, patch_[t], std::abs(h), h >= 0 ? normal_[t] : -1.0 * normal_[t]);
          } else if (cl.region <= kEdgeCA) {
            add(kEdgeHit, tri_edges_[t][cl.region - kEdgeAB], dist, dist > 0 ? (1.0 / dist) * d : normal_[t]);
          } else {
            add(kVertexHit, v[cl.region - kVertexA], dist, dist > 0 ? (1.0 / dist) * d : normal_[t]);
          }
        }
      }

  // Face > edge > vertex: drop an edge next to a touched face, a vertex next to a touched face or edge.
  auto face_touched = [&](std::uint32_t patch) {
    for (int c = 0; c < n_cand; ++c)
      if (cand[c].kind == kFaceHit && cand[c].id == patch) return true;
    return false;
  };
  auto edge_touched = [&](std::uint32_t e) {
    for (int c = 0; c < n_cand; ++c)
      if (cand[c].kind == kEdgeHit && cand[c].id == e) return true;
    return false;
  };
  int out = 0;
  for (int c = 0; c < n_cand && out < cap; ++c) {
    const Candidate& h = cand[c];
    bool keep = true;
    if (h.kind == kEdgeHit) {
      for (std::uint32_t m = edge_tri_start_[h.id]; m < edge_tri_start_[h.id + 1] && keep; ++m) {
        keep = !face_touched(patch_[edge_tri_[m]]);
      }
    } else if (h.kind == kVertexHit) {
      for (std::uint32_t m = vert_tri_start_[h.id]; m < vert_tri_start_[h.id + 1] && keep; ++m) {
        keep = !face_touched(patch_[vert_tri_[m]]);
      }
      for (std::uint32_t m = vert_edge_start_[h.id]; m < vert_edge_start_[h.id + 1] && keep; ++m) {
        keep = !edge_touched(vert_edge_[m]);
      }
    }
    if (!keep) continue;
    const int base = h.kind == kFaceHit ? 0
                     : h.kind == kEdgeHit ? static_cast<int>(patch_count_)
                                          : static_cast<int>(patch_count_ + edge_vertices_.size());
    hits[out++] = {h.normal, h.distance, base + static_cast<int>(h.id)};
  }
  return out;
}

void MeshGeometry::bounds(Vec3& lo, Vec3& hi) const {
  lo = lo_;
  hi = hi_;
}

std::string MeshGeometry::describe() const {
  std::ostringstream s;
  s << label_ << ": " << mesh_.triangles.size() << " triangles, " << patch_count_ << " planar patches, bins of "
    << cell_ << " m";
  return s.str();
}

}  // namespace grainscale::dem
