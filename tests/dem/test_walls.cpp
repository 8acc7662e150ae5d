// Analytic wall geometries: which features a sphere touches, with what normal and distance.
#include <catch2/catch.hpp>
#include <cmath>

#include "dem/wall.hpp"
#include "dem/walls/box.hpp"
#include "dem/walls/cylinder.hpp"
#include "dem/walls/plane.hpp"

using namespace grainscale::dem;
using Catch::Matchers::WithinAbs;

TEST_CASE("A sphere in the corner of a box touches three faces, one feature each", "[dem][walls]") {
  const BoxGeometry box({0, 0, 0}, {1, 1, 1});
  WallHit hits[8];
  const int n = box.nearby({0.05, 0.05, 0.05}, 0.1, hits, 8);
  REQUIRE(n == 3);
  CHECK(hits[0].feature != hits[1].feature);
  CHECK(hits[1].feature != hits[2].feature);
  for (int k = 0; k < 3; ++k) CHECK_THAT(hits[k].distance, WithinAbs(0.05, 1e-15));
  CHECK(box.nearby({0.5, 0.5, 0.5}, 0.1, hits, 8) == 0);  // far from every face
}

TEST_CASE("An open-topped box has no lid, and ignores a particle that left over the rim", "[dem][walls]") {
  const BoxGeometry box({0, 0, 0}, {1, 1, 1}, {true, true, true, true, true, false});
  WallHit hits[8];
  CHECK(box.nearby({0.5, 0.5, 0.97}, 0.05, hits, 8) == 0);  // near the open top
  CHECK(box.nearby({-0.02, 0.5, 1.2}, 0.05, hits, 8) == 0);  // outside, above the rim
  REQUIRE(box.nearby({0.5, 0.5, 0.02}, 0.05, hits, 8) == 1);  // floor
  CHECK(hits[0].normal.z == 1.0);
}

TEST_CASE("Cylinder walls: inside a pipe with a floor, and outside a capped post", "[dem][walls]") {
  WallHit hits[8];
  const CylinderGeometry pipe(0.05, 0.0, 0.3, true, true, false);
  REQUIRE(pipe.nearby({0.048, 0, 0.1}, 0.005, hits, 8) == 1);
  CHECK_THAT(hits[0].distance, WithinAbs(0.002, 1e-15));
  CHECK_THAT(hits[0].normal.x, WithinAbs(-1, 1e-15));  // points inwards, towards the centre
  CHECK(pipe.nearby({0, 0.048, 0.003}, 0.005, hits, 8) == 2);  // side and floor at the bottom edge

  const CylinderGeometry post(0.05, 0.0, 0.3, false, true, true);
  REQUIRE(post.nearby({0.053, 0, 0.1}, 0.005, hits, 8) == 1);
  CHECK_THAT(hits[0].normal.x, WithinAbs(1, 1e-15));
  // Diagonally beyond the top rim: one contact with the rim edge, normal along the diagonal.
  REQUIRE(post.nearby({0.053, 0, 0.303}, 0.005, hits, 8) == 1);
  CHECK_THAT(hits[0].normal.x, WithinAbs(std::sqrt(0.5), 1e-12));
  CHECK_THAT(hits[0].normal.z, WithinAbs(std::sqrt(0.5), 1e-12));
}

TEST_CASE("A wall's pose moves its geometry and gives the surface velocity", "[dem][walls]") {
  // A floor through the origin, turned 90 degrees about x: its normal now points along -y.
  WallPose pose;
  pose.origin = {0, 1, 0};
  pose.orientation = axis_angle({1, 0, 0}, M_PI / 2);
  pose.angular_velocity = {0, 0, 2};
  const Wall w("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 0, pose);
  WallContact c[4];
  REQUIRE(w.contacts({0.3, 0.98, 0}, 0.05, c, 4) == 1);
  CHECK_THAT(c[0].normal.y, WithinAbs(-1, 1e-12));
  CHECK_THAT(c[0].overlap, WithinAbs(0.03, 1e-12));
  const Vec3 v = pose.surface_velocity(c[0].point);
  CHECK_THAT(v.y, WithinAbs(2 * 0.3, 1e-12));  // omega x r with r = (0.3, 0, 0)
}
