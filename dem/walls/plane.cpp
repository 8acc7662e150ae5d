#include "dem/walls/plane.hpp"

#include <limits>
#include <sstream>

namespace grainscale::dem {

PlaneGeometry::PlaneGeometry(const Vec3& point, const Vec3& normal) : point_(point), normal_((1.0 / norm(normal)) * normal) {}

int PlaneGeometry::nearby(const Vec3& p, double reach, WallHit* hits, int cap) const {
  const double d = dot(p - point_, normal_);
  if (cap < 1 || d < 0 || d >= reach) return 0;
  hits[0] = {normal_, d, 0};
  return 1;
}

void PlaneGeometry::bounds(Vec3& lo, Vec3& hi) const {
  const double inf = std::numeric_limits<double>::infinity();
  lo = {-inf, -inf, -inf};
  hi = {inf, inf, inf};
}

std::string PlaneGeometry::describe() const {
  std::ostringstream s;
  s << "plane through (" << point_.x << ", " << point_.y << ", " << point_.z << ") normal (" << normal_.x << ", "
    << normal_.y << ", " << normal_.z << ")";
  return s.str();
}

}  // namespace grainscale::dem
