#include "dem/walls/box.hpp"

#include <sstream>

namespace grainscale::dem {

BoxGeometry::BoxGeometry(const Vec3& lo, const Vec3& hi, std::array<bool, 6> closed) : lo_(lo), hi_(hi), closed_(closed) {}

int BoxGeometry::nearby(const Vec3& p, double reach, WallHit* hits, int cap) const {
  const double lo[3] = {lo_.x, lo_.y, lo_.z};
  const double hi[3] = {hi_.x, hi_.y, hi_.z};
  const double c[3] = {p.x, p.y, p.z};
  for (int a = 0; a < 3; ++a) {
    if (c[a] < lo[a] || c[a] > hi[a]) return 0;  // centre outside: escaped over an open rim
  }
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    Vec3 e{};
    (a == 0 ? e.x : a == 1 ? e.y : e.z) = 1.0;
    const double d_lo = c[a] - lo[a];
    const double d_hi = hi[a] - c[a];
    if (closed_[2 * a] && d_lo < reach && n < cap) hits[n++] = {e, d_lo, 2 * a};
    if (closed_[2 * a + 1] && d_hi < reach && n < cap) hits[n++] = {-e, d_hi, 2 * a + 1};
  }
  return n;
}

void BoxGeometry::bounds(Vec3& lo, Vec3& hi) const {
  lo = lo_;
  hi = hi_;
}

std::string BoxGeometry::describe() const {
  std::ostringstream s;
  s << "box inside [" << lo_.x << ", " << hi_.x << "] x [" << lo_.y << ", " << hi_.y << "] x [" << lo_.z << ", "
    << hi_.z << "]";
  return s.str();
}

}  // namespace grainscale::dem
