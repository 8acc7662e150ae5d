#include "dem/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"

namespace grainscale::dem {

void TriangleMesh::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto n = static_cast<std::uint32_t>(vertices.size());
  vertices.push_back(a);
  vertices.push_back(b);
  vertices.push_back(c);
  triangles.push_back({n, n + 1, n + 2});
}

void TriangleMesh::add_quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  add_triangle(a, b, c);
  add_triangle(a, c, d);
}

void TriangleMesh::append(const TriangleMesh& other) {
  const auto n = static_cast<std::uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto t : other.triangles) triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
}

void TriangleMesh::bounds(Vec3& lo, Vec3& hi) const {
  const double inf = std::numeric_limits<double>::infinity();
  lo = {inf, inf, inf};
  hi = {-inf, -inf, -inf};
  for (const Vec3& v : vertices) {
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  }
}

void TriangleMesh::weld(double tolerance) {
  // Snap to a grid of cell `tolerance` and merge vertices that land in the same or a neighbouring
  // cell within the tolerance; deterministic (first occurrence wins).
  std::map<std::tuple<long long, long long, long long>, std::vector<std::uint32_t>> grid;
  std::vector<std::uint32_t> remap(vertices.size());
  std::vector<Vec3> kept;
  auto key = [&](const Vec3& v) {
    return std::tuple<long long, long long, long long>{std::llround(v.x / tolerance), std::llround(v.y / tolerance),
                                                       std::llround(v.z / tolerance)};
  };
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec3 v = vertices[i];
    const auto [kx, ky, kz] = key(v);
    std::int64_t found = -1;
    for (long long dx = -1; dx <= 1 && found < 0; ++dx)
      for (long long dy = -1; dy <= 1 && found < 0; ++dy)
        for (long long dz = -1; dz <= 1 && found < 0; ++dz) {
          auto it = grid.find({kx + dx, ky + dy, kz + dz});
          if (it == grid.end()) continue;
          for (std::uint32_t k : it->second)
            if (norm(kept[k] - v) <= tolerance) {
              found = k;
              break;
            }
        }
    if (found < 0) {
      found = static_cast<std::int64_t>(kept.size());
      kept.push_back(v);
      grid[{kx, ky, kz}].push_back(static_cast<std::uint32_t>(found));
    }
    remap[i] = static_cast<std::uint32_t>(found);
  }
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (auto t : triangles) {
    const std::array<std::uint32_t, 3> r{remap[t[0]], remap[t[1]], remap[t[2]]};
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
    if (norm(cross(kept[r[1]] - kept[r[0]], kept[r[2]] - kept[r[0]])) <= tolerance * tolerance) continue;
    tris.push_back(r);
  }
  vertices = std::move(kept);
  triangles = std::move(tris);
}

namespace {

double weld_tolerance(const TriangleMesh& m) {
  Vec3 lo, hi;
  m.bounds(lo, hi);
  return 1e-9 * std::max(norm(hi - lo), 1e-300);
}

TriangleMesh read_ascii(const std::string& path, const std::string& text, double scale) {
  TriangleMesh m;
  std::istringstream in(text);
  std::string line;
  int line_no = 0, corners = 0;
  Vec3 c[3];
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word) || word != "vertex") continue;
    double x, y, z;
    std::string extra;
    if (!(ls >> x >> y >> z) || (ls >> extra) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      throw InputError(path + ":" + std::to_string(line_no) + ": 'vertex' needs three finite numbers");
    }
    c[corners++] = scale * Vec3{x, y, z};
    if (corners == 3) {
      m.add_triangle(c[0], c[1], c[2]);
      corners = 0;
    }
  }
  if (corners != 0) throw InputError(path + ": ASCII STL ends inside a facet (vertex count not a multiple of 3)");
  return m;
}

TriangleMesh read_binary(const std::string& path, const std::string& data, double scale) {
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  if (data.size() != 84 + 50ull * count) {
    throw InputError(path + ": binary STL declares " + std::to_string(count) + " triangles (" +
                     std::to_string(84 + 50ull * count) + " bytes) but the file has " + std::to_string(data.size()) +
                     " bytes");
  }
  TriangleMesh m;
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* rec = data.data() + 84 + 50ull * t + 12;  // skip the stored normal (recomputed)
    Vec3 c[3];
    for (int k = 0; k < 3; ++k) {
      float f[3];
      std::memcpy(f, rec + 12 * k, 12);
      if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2])) {
        throw InputError(path + ": triangle " + std::to_string(t) + " has a non-finite coordinate");
      }
      c[k] = scale * Vec3{f[0], f[1], f[2]};
    }
    m.add_triangle(c[0], c[1], c[2]);
  }
  return m;
}

}  // namespace

TriangleMesh load_stl(const std::string& path, double scale) {
  if (!(scale > 0) || !std::isfinite(scale)) throw InputError(path + ": scale must be > 0");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the STL file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Binary files may also begin with "solid" in their header; decide by the size check first.
  bool binary = false;
  if (data.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    binary = data.size() == 84 + 50ull * count;
  }
  const bool ascii = !binary && data.compare(0, 5, "solid") == 0;
  if (!binary && !ascii) {
    if (data.size() >= 84) return read_binary(path, data, scale);  // throws with the size mismatch
    throw InputError(path + ": not an STL file (no 'solid' header and too short for binary STL)");
  }
  TriangleMesh m = binary ? read_binary(path, data, scale) : read_ascii(path, data, scale);
  if (m.triangles.empty()) throw InputError(path + ": the STL file has no triangles");
  m.weld(weld_tolerance(m));
  if (m.triangles.empty()) throw InputError(path + ": every triangle in the STL file is degenerate (zero area)");
  return m;
}

void write_stl(const TriangleMesh& mesh, const std::string& path) {
  std::string out(80, '\0');
  const char* header = "grainscale generated mesh";
  std::memcpy(out.data(), header, std::strlen(header));
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (auto t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    Vec3 n = cross(b - a, c - a);
    n = (1.0 / norm(n)) * n;
    for (const Vec3& v : {n, a, b, c}) {
      const float f[3] = {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
      out.append(reinterpret_cast<const char*>(f), 12);
    }
    out.append(2, '\0');
  }
  write_file_atomically(path, out);
}

}  // namespace grainscale::dem
