#include "dem/container_meshes.hpp"

#include <cmath>
#include <numbers>

#include "dem/input_error.hpp"

namespace grainscale::dem {

namespace {

Vec3 on_circle(double r, int k, int segments, double z) {
  const double a = 2 * std::numbers::pi * k / segments;
  return {r * std::cos(a), r * std::sin(a), z};
}

void add_disc(TriangleMesh& m, double r, int segments, double z) {
  for (int k = 0; k < segments; ++k) m.add_triangle({0, 0, z}, on_circle(r, k, segments, z), on_circle(r, k + 1, segments, z));
}

void add_band(TriangleMesh& m, double r, int segments, double z0, double z1) {
  for (int k = 0; k < segments; ++k) {
    m.add_quad(on_circle(r, k, segments, z0), on_circle(r, k + 1, segments, z0), on_circle(r, k + 1, segments, z1),
               on_circle(r, k, segments, z1));
  }
}

void check_segments(int segments) {
  if (segments < 8 || segments > 4096) throw InputError("segments must be in [8, 4096], got " + std::to_string(segments));
}

double weld_tolerance(const TriangleMesh& m) {
  Vec3 lo, hi;
  m.bounds(lo, hi);
  return 1e-9 * norm(hi - lo);
}

}  // namespace

TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi, std::array<bool, 6> closed, int compartments) {
  if (compartments < 1 || compartments > 1000) throw InputError("compartments must be in [1, 1000]");
  TriangleMesh m;
  const double x0 = lo.x, x1 = hi.x, y0 = lo.y, y1 = hi.y, z0 = lo.z, z1 = hi.z;
  if (closed[0]) m.add_quad({x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1});
  if (closed[1]) m.add_quad({x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0});
  if (closed[2]) m.add_quad({x0, y0, z0}, {x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0});
  if (closed[3]) m.add_quad({x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1});
  if (closed[4]) m.add_quad({x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0});
  if (closed[5]) m.add_quad({x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1});
  for (int k = 1; k < compartments; ++k) {
    const double x = x0 + (x1 - x0) * k / compartments;
    m.add_quad({x, y0, z0}, {x, y1, z0}, {x, y1, z1}, {x, y0, z1});
  }
  m.weld(weld_tolerance(m));
  return m;
}

TriangleMesh pipe_mesh(double radius, double length, int segments) {
  check_segments(segments);
  TriangleMesh m;
  add_band(m, radius, segments, 0, length);
  m.weld(weld_tolerance(m));
  return m;
}

TriangleMesh tray_mesh(double radius, double rim_height, int segments) {
  check_segments(segments);
  TriangleMesh m;
  add_disc(m, radius, segments, 0);
  if (rim_height > 0) add_band(m, radius, segments, 0, rim_height);
  m.weld(weld_tolerance(m));
  return m;
}

TriangleMesh cylinder_mesh(double radius, double height, int segments, bool bottom, bool top) {
  check_segments(segments);
  TriangleMesh m;
  add_band(m, radius, segments, 0, height);
  if (bottom) add_disc(m, radius, segments, 0);
  if (top) add_disc(m, radius, segments, height);
  m.weld(weld_tolerance(m));
  return m;
}

}  // namespace grainscale::dem
