#pragma once
// The inside of an axis-aligned box [lo, hi] (in its body frame), each of the six faces present or
// open (an open-topped container has no +z face). A sphere whose centre is inside the box touches a
// face when it is closer than its radius; near an edge or corner it touches two or three faces,
// each its own feature with its own history, which is exact for the inside of a box. A sphere whose
// centre has left the box (over the rim of an open face) no longer interacts with it.
#include <array>

#include "dem/wall.hpp"

namespace grainscale::dem {

class BoxGeometry final : public WallGeometry {
 public:
  /// Face order: -x, +x, -y, +y, -z, +z.
  BoxGeometry(const Vec3& lo, const Vec3& hi, std::array<bool, 6> closed = {true, true, true, true, true, true});
  int nearby(const Vec3& p, double reach, WallHit* hits, int cap) const override;
  void bounds(Vec3& lo, Vec3& hi) const override;
  std::string describe() const override;

 private:
  Vec3 lo_, hi_;
  std::array<bool, 6> closed_;
};

}  // namespace grainscale::dem
