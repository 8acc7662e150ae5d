#pragma once
// A cylinder of radius R about the body z axis between z0 and z1. `inside` = true: particles live
// inside (a pipe or a tray), optionally with a bottom and/or top cap; false: particles live outside
// (a post), and the caps close the post's ends.
#include "dem/wall.hpp"

namespace grainscale::dem {

class CylinderGeometry final : public WallGeometry {
 public:
  CylinderGeometry(double radius, double z0, double z1, bool inside, bool bottom_cap, bool top_cap);
  int nearby(const Vec3& p, double reach, WallHit* hits, int cap) const override;
  void bounds(Vec3& lo, Vec3& hi) const override;
  std::string describe() const override;

 private:
  double radius_, z0_, z1_;
  bool inside_, bottom_, top_;
};

}  // namespace grainscale::dem
