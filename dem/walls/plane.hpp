#pragma once
// An infinite plane through `point` with unit normal `normal`; particles live on the normal side.
// A particle whose centre has crossed to the back side is not pushed (it has been lost, and the
// blow-up check reports it) rather than launched with a huge overlap.
#include "dem/wall.hpp"

namespace grainscale::dem {

class PlaneGeometry final : public WallGeometry {
 public:
  PlaneGeometry(const Vec3& point, const Vec3& normal);
  int nearby(const Vec3& p, double reach, WallHit* hits, int cap) const override;
  void bounds(Vec3& lo, Vec3& hi) const override;
  std::string describe() const override;

 private:
  Vec3 point_, normal_;
};

}  // namespace grainscale::dem
