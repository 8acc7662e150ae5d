// The force loop's bookkeeping of which neighbour-list entries touch (dem/force_field.hpp): a pair
// that parts exerts exactly no force and its tangential history is cleared (Luding 2008: the Mindlin
// spring starts afresh at every new contact), whether it parts between two force evaluations or a
// list rebuild carries a history over to a pair that is already apart.
#include <catch2/catch.hpp>

#include <limits>
#include <memory>
#include <vector>

#include "dem/force_field.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/walls/plane.hpp"

#include "list_fixture.hpp"
#include "pass_one_loop.hpp"

using namespace grainscale::dem;

namespace {

struct TwoSpheres {
  MaterialTable materials;
  Particles p;
  NeighborList nl;
  ForceField ff;
  std::vector<Wall> walls;
  const double r = 0.003, skin = 0.002, dt = 1e-6;

  TwoSpheres() {
    const int m = materials.add({"grain", 1380, 2.6e6, 0.3});
    materials.set_pair(m, m, {0.5, 0.35, 0.08, true});
    p.add_sphere(0, m, r, 1380, {0, 0, 0});
    p.add_sphere(1, m, r, 1380, {2 * r - 1e-4, 0, 0}, {0, 0.05, 0});  // overlapping, sliding along y
    ff.setup(materials, walls, RollingSettings{});
    rebuild();
  }
  void rebuild() {
    grainscale::dem::testing::build_list(nl, p, skin);
  }
  ContactHistory history() const {
    REQUIRE(nl.entries() == 1);
    return nl.history(0);
  }
};

}  // namespace

TEST_CASE("A pair that parts exerts no force and its tangential history starts afresh", "[dem][contact]") {
  TwoSpheres s;
  const ForceDiagnostics touching = s.ff.compute(s.p, s.nl, s.walls, s.dt);
  REQUIRE(touching.contacts == 1);
  CHECK(norm2(s.p.force[0]) > 0);
  CHECK(norm2(s.history().shear) > 0);  // the Mindlin spring has stretched along y

  // Apart, but still inside the skin: the same list entry, no rebuild.
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (s.p.id[i] == 1) s.p.x[i].x += 5e-4;
  }
  const ForceDiagnostics apart = s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK(apart.contacts == 0);
  REQUIRE(s.nl.entries() == 1);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    CHECK(s.p.force[i] == Vec3{});
    CHECK(s.p.torque[i] == Vec3{});
  }
  CHECK(s.history().shear == Vec3{});
  CHECK(s.history().rolling == Vec3{});

  // A rebuilt list that carries a (stale) history to a pair already apart: cleared at the next step.
  s.nl.shear(0) = {1e-5, 0, 0};
  s.rebuild();
  s.nl.shear(0) = {0, 1e-5, 0};
  s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK(s.history().shear == Vec3{});
  for (std::size_t i = 0; i < s.p.size(); ++i) CHECK(s.p.force[i] == Vec3{});

  // Touching again: the spring starts from zero, so the first step's shear is one step of sliding.
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (s.p.id[i] == 1) s.p.x[i].x -= 5e-4;
  }
  s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK(norm(s.history().shear) == Approx(0.05 * s.dt).epsilon(1e-6));
}

TEST_CASE("Only a rolling model with a spring keeps one in the contact history", "[dem][contact][rolling]") {
  // The history holds the EPSD spring torque M_k (Ai et al. 2011, eq. 13) beside the Mindlin
  // spring; the constant-torque and no-rolling models have no spring, never read it and leave it
  // zero. A spring left by an EPSD run (its checkpoint restarted under constant torque) is dropped.
  TwoSpheres s;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (s.p.id[i] == 1) s.p.omega[i] = {0, 0, 20};  // rolling about z on sphere 0 (contact normal x)
  }
  RollingSettings epsd;
  epsd.model = RollingModel::epsd;
  s.ff.setup(s.materials, s.walls, epsd);
  s.ff.compute(s.p, s.nl, s.walls, s.dt);
  REQUIRE(norm2(s.history().rolling) > 0);
  const Vec3 shear = s.history().shear;

  // The same contact and Mindlin spring, once with the EPSD spring left over and once without.
  TwoSpheres fresh;
  for (std::size_t i = 0; i < fresh.p.size(); ++i) fresh.p.omega[i] = s.p.omega[i];
  fresh.ff.compute(fresh.p, fresh.nl, fresh.walls, fresh.dt);  // (flags the entry as touching)
  fresh.nl.shear(0) = shear;
  fresh.ff.compute(fresh.p, fresh.nl, fresh.walls, fresh.dt);
  s.nl.shear(0) = shear;
  s.ff.setup(s.materials, s.walls, RollingSettings{});  // constant torque
  s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK(s.history().rolling == Vec3{});
  CHECK(fresh.history().rolling == Vec3{});
  CHECK(norm2(s.history().shear) > 0);
  CHECK(s.history().shear == fresh.history().shear);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    CHECK(s.p.force[i] == fresh.p.force[i]);
    CHECK(s.p.torque[i] == fresh.p.torque[i]);
    CHECK(norm2(s.p.torque[i]) > 0);
  }
  // Without a spring the list holds none at all (its memory is given back), and a build keeps it so;
  // back under EPSD every entry's spring starts at zero and grows again.
  CHECK_FALSE(s.nl.keeps_rolling_springs());
  s.rebuild();
  s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK_FALSE(s.nl.keeps_rolling_springs());
  CHECK(s.history().rolling == Vec3{});
  s.ff.setup(s.materials, s.walls, epsd);
  s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK(s.nl.keeps_rolling_springs());
  CHECK(norm2(s.history().rolling) > 0);
}

TEST_CASE("A static wall is asked about the spheres within reach of it at the list build, and again after it is moved",
          "[dem][walls]") {
  // ForceField skips static walls that cannot reach a sphere before the next list build. Two ways
  // that could miss a contact: a sphere far from the wall at the build, and a wall given a new pose
  // between steps (no build in between).
  TwoSpheres s;
  s.walls.emplace_back("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 0,
                       WallPose{{0, 0, -0.02}, {}, {}, {}});  // 20 mm below the spheres: out of reach
  s.ff.setup(s.materials, s.walls, RollingSettings{});
  s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK(s.ff.compute(s.p, s.nl, s.walls, s.dt).wall_contacts == 0);

  // The floor is raised to 0.1 mm inside both spheres, with no list build: both must feel it.
  WallPose raised{{0, 0, -s.r + 1e-4}, {}, {}, {}};
  s.walls[0].set_pose(raised);
  const ForceDiagnostics d = s.ff.compute(s.p, s.nl, s.walls, s.dt);
  CHECK(d.wall_contacts == 2);
  for (std::size_t i = 0; i < s.p.size(); ++i) CHECK(s.p.force[i].z > 0);

  // A sphere that falls from out of reach onto a static floor is caught once the list is rebuilt
  // (moved more than skin/2), with the same force as a wall asked at every step.
  for (std::size_t i = 0; i < s.p.size(); ++i) s.p.x[i].z += 0.01;  // out of reach again
  s.rebuild();
  CHECK(s.ff.compute(s.p, s.nl, s.walls, s.dt).wall_contacts == 0);
  for (std::size_t i = 0; i < s.p.size(); ++i) s.p.x[i].z -= 0.01;  // back, 0.1 mm deep
  s.rebuild();
  CHECK(s.ff.compute(s.p, s.nl, s.walls, s.dt).wall_contacts == 2);
}

TEST_CASE("A non-finite force or torque is reported at the first slot that has one, with or without wall contacts",
          "[dem][contact]") {
  // The blow-up check (Simulation::check_health) names the particle from ForceDiagnostics::bad_slot.
  // Pass 2 tests a sphere's sums as it finishes them, or, for a sphere at a wall, as its batched wall
  // contacts are added: either way an infinity or a NaN in any of the six components is caught, and a
  // finite state reports none.
  const int where = GENERATE(0, 1, 2);  // the pair's first sphere, its second, a sphere on the floor
  const int component = GENERATE(0, 1, 2, 3, 4, 5);  // which of v, omega goes bad (and so f or t)
  const double bad = GENERATE(std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN());
  // Both loops: beds beyond the caches list the spheres near a wall first and check every sphere's
  // sums in one branch-free loop; beds within them check each sphere as they come to it.
  const bool chunked = GENERATE(false, true);
  INFO("the loop of beds " << (chunked ? "beyond" : "within") << " the caches");
  const grainscale::dem::testing::PassOneLoop loop(chunked);
  MaterialTable materials;
  const int m = materials.add({"grain", 1380, 2.6e6, 0.3});
  materials.set_pair(m, m, {0.5, 0.35, 0.08, true});
  const double r = 0.003, skin = 0.001, dt = 1e-6;
  Particles p;
  p.add_sphere(0, m, r, 1380, {0.05, 0.05, 0.05});
  p.add_sphere(1, m, r, 1380, {0.05 + 2 * r - 1e-4, 0.05, 0.05});
  p.add_sphere(2, m, r, 1380, {0.2, 0.2, r - 1e-4});  // pressed into the floor, apart from the pair
  std::vector<Wall> walls;
  walls.emplace_back("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), m);
  NeighborList nl;
  grainscale::dem::testing::build_list(nl, p, skin);
  ForceField ff;
  ff.setup(materials, walls, RollingSettings{});
  REQUIRE(ff.compute(p, nl, walls, dt).bad_slot == -1);

  std::size_t slot = 0;
  while (p.id[slot] != static_cast<std::uint64_t>(where)) ++slot;
  // A bad velocity component spoils the force; a bad angular velocity component the torque (through
  // the tangential force, and for the constant-torque rolling model directly).
  double* v = component < 3 ? &p.v[slot].x : &p.omega[slot].x;
  v[component % 3] = bad;
  const ForceDiagnostics d = ff.compute(p, nl, walls, dt);
  INFO("sphere id " << where << ", component " << component << ", value " << bad);
  CHECK(d.bad_slot >= 0);
  if (d.bad_slot >= 0) CHECK((p.id[d.bad_slot] == 0 || p.id[d.bad_slot] == 1 || p.id[d.bad_slot] == 2));
  if (where == 2) CHECK(d.bad_slot == static_cast<std::int64_t>(slot));  // alone: only it goes bad
  CHECK(d.wall_contacts == 1);
}
