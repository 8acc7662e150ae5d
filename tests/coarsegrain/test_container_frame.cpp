// Container frame: the transform of docs/snapshot_layout.md, its inverse, and the choice of pose.
#include <catch2/catch.hpp>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/container_frame.hpp"
#include "dem/input_error.hpp"
#include "synthetic_snapshot.hpp"

using namespace grainscale;
using namespace grainscale::cg;
using Catch::Matchers::WithinAbs;

namespace {

ContainerPose tilted_moving_pose() {
  ContainerPose p;
  p.origin = {0.3, -1.2, 0.45};
  p.orientation = dem::normalized(dem::axis_angle(dem::Vec3{0.2, 1.0, -0.3} * (1.0 / std::sqrt(1.13)), 0.41));
  p.velocity = {0.05, -0.02, 0.01};
  p.angular_velocity = {0.0, 0.17, 0.03};
  return p;
}

void check_close(const Vec3& a, const Vec3& b, double tol) {
  CHECK_THAT(a.x, WithinAbs(b.x, tol));
  CHECK_THAT(a.y, WithinAbs(b.y, tol));
  CHECK_THAT(a.z, WithinAbs(b.z, tol));
}

}  // namespace

TEST_CASE("Container frame: positions and velocities round-trip through the world frame", "[cg][frame]") {
  const ContainerPose pose = tilted_moving_pose();
  const Vec3 xc{0.12, 0.05, 0.031}, vc{-0.4, 0.2, 0.7};
  const Vec3 xw = to_world_position(pose, xc);
  const Vec3 vw = to_world_velocity(pose, xc, vc);
  check_close(to_container_position(pose, xw), xc, 1e-15);
  check_close(to_container_velocity(pose, xw, vw), vc, 1e-15);
}

TEST_CASE("Container frame: a particle carried rigidly by the container is at rest in its frame", "[cg][frame]") {
  const ContainerPose pose = tilted_moving_pose();
  const Vec3 xc{0.7, 0.1, 0.02};
  const Vec3 xw = to_world_position(pose, xc);
  // Rigid-body velocity of the material point at xw: V + omega x (x - origin).
  const Vec3 vw = pose.velocity + cross(pose.angular_velocity, xw - pose.origin);
  check_close(to_container_velocity(pose, xw, vw), {}, 1e-16);
  // The frame's own axes: world direction R e_x is the container's x.
  check_close(to_container_position(pose, pose.origin + dem::rotate(pose.orientation, {1, 0, 0})), {1, 0, 0}, 1e-15);
}

TEST_CASE("Container pose comes from a named wall of the snapshot, identity by default", "[cg][frame]") {
  dem::Snapshot s = test::empty_snapshot({"wheat"});
  const ContainerPose want = tilted_moving_pose();
  s.walls.push_back({"floor", {}, {}, {}, {}});
  s.walls.push_back({"box", want.origin, want.orientation, want.velocity, want.angular_velocity});
  const ContainerPose got = container_pose(s, "box");
  check_close(got.origin, want.origin, 0);
  CHECK(got.orientation.w == Approx(want.orientation.w).epsilon(1e-15));
  check_close(got.angular_velocity, want.angular_velocity, 0);
  const ContainerPose id = container_pose(s, "");
  check_close(id.origin, {}, 0);
  CHECK(id.orientation.w == 1.0);
  REQUIRE_THROWS_AS(container_pose(s, "lid"), InputError);
  REQUIRE_THROWS_WITH(container_pose(s, "lid"), Catch::Contains("floor, box"));
}

TEST_CASE("Particles in a moved container frame: positions, velocities and body counts", "[cg][frame]") {
  dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
  const ContainerPose pose = tilted_moving_pose();
  const Vec3 xc{0.2, 0.1, 0.05}, vc{0.3, 0, -0.1};
  test::add_sphere(s, 1, 0.002, 100, to_world_position(pose, xc), to_world_velocity(pose, xc, vc));
  s.walls.push_back({"box", pose.origin, pose.orientation, pose.velocity, pose.angular_velocity});
  const SpeciesTable species = species_from_snapshot(s, {"chaff"});
  REQUIRE(species.chaff == std::vector<bool>{false, true});
  const CgParticles p = container_particles(s, container_pose(s, "box"), species);
  REQUIRE(p.size() == 1);
  check_close(p.position[0], xc, 1e-15);
  check_close(p.velocity[0], vc, 1e-15);
  check_close(p.body_position[0], xc, 1e-15);
  CHECK(p.species[0] == 1);
  CHECK(p.number[0] == 1.0);
  CHECK_THAT(p.volume[0], WithinAbs(4.0 / 3.0 * test::kPi * 8e-9, 1e-22));
}
