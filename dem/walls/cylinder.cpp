#include "dem/walls/cylinder.hpp"

#include <cmath>
#include <sstream>

namespace grainscale::dem {

CylinderGeometry::CylinderGeometry(double radius, double z0, double z1, bool inside, bool bottom_cap, bool top_cap)
    : radius_(radius), z0_(z0), z1_(z1), inside_(inside), bottom_(bottom_cap), top_(top_cap) {}

int CylinderGeometry::nearby(const Vec3& p, double reach, WallHit* hits, int cap) const {
  const double rho = std::hypot(p.x, p.y);
  int n = 0;
  if (inside_) {
    if (rho > radius_ || p.z < z0_ || p.z > z1_) return 0;  // centre outside the cylinder
    const double d_side = radius_ - rho;
    if (d_side < reach && rho > 0 && n < cap) hits[n++] = {{-p.x / rho, -p.y / rho, 0}, d_side, 0};
    if (bottom_ && p.z - z0_ < reach && n < cap) hits[n++] = {{0, 0, 1}, p.z - z0_, 1};
    if (top_ && z1_ - p.z < reach && n < cap) hits[n++] = {{0, 0, -1}, z1_ - p.z, 2};
    return n;
  }
  // Outside a solid post: closest point on the (capped) cylinder surface.
  const bool within_z = p.z >= z0_ && p.z <= z1_;
  if (within_z) {
    const double d = rho - radius_;
    if (d >= 0 && d < reach && cap > 0) {
      hits[n++] = {{p.x / rho, p.y / rho, 0}, d, 0};
    }
    return n;
  }
  const bool below = p.z < z0_;
  if ((below && !bottom_) || (!below && !top_)) return 0;
  const double dz = below ? z0_ - p.z : p.z - z1_;
  if (rho <= radius_) {
    if (dz < reach && cap > 0) hits[n++] = {{0, 0, below ? -1.0 : 1.0}, dz, below ? 1 : 2};
    return n;
  }
  // Beyond the rim edge: contact with the circular edge.
  const double dr = rho - radius_;
  const double d = std::hypot(dr, dz);
  if (d < reach && cap > 0) {
    const Vec3 nrm{dr * p.x / (rho * d), dr * p.y / (rho * d), (below ? -dz : dz) / d};
    hits[n++] = {nrm, d, below ? 3 : 4};
  }
  return n;
}

void CylinderGeometry::bounds(Vec3& lo, Vec3& hi) const {
  lo = {-radius_, -radius_, z0_};
  hi = {radius_, radius_, z1_};
}

std::string CylinderGeometry::describe() const {
  std::ostringstream s;
  s << "cylinder r=" << radius_ << " z=[" << z0_ << ", " << z1_ << "] " << (inside_ ? "inside" : "outside");
  return s.str();
}

}  // namespace grainscale::dem
