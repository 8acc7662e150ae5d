// Partner shares in rings (dem/force_field.hpp, share_ring_entries): in beds beyond the caches each
// thread keeps the shares its completion front reads in a ring, not one per list entry. Where a
// share lives must not change a number: the same trajectory bit for bit with no ring, the default
// ring and the smallest one, whose guard must evaluate the batch early to keep the shares it still
// holds, on 1, 2 and 3 threads (whose ranges leave their first spheres' shares to the array).
#include <omp.h>

#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

#include <random>

#include "barley_box_fixture.hpp"
#include "list_fixture.hpp"
#include "pressed_spheres_fixture.hpp"
#include "parallel_everything.hpp"
#include "pass_one_loop.hpp"

using namespace grainscale::dem;

namespace {

/// Sets the rings' size for the life of the object.
struct RingSize {
  std::size_t saved = share_ring_entries();
  explicit RingSize(std::size_t entries) { share_ring_entries() = entries; }
  ~RingSize() { share_ring_entries() = saved; }
  RingSize(const RingSize&) = delete;
  RingSize& operator=(const RingSize&) = delete;
};

/// Position, velocity, angular velocity, force and torque of every sphere, by id.
std::vector<double> state(const Simulation& sim) {
  const Particles& p = sim.particles();
  std::vector<double> out(p.size() * 15);
  for (std::size_t s = 0; s < p.size(); ++s) {
    const Vec3* f[5] = {&p.x[s], &p.v[s], &p.omega[s], &p.force[s], &p.torque[s]};
    for (int a = 0; a < 5; ++a) {
      double* to = &out[p.id[s] * 15 + 3 * a];
      to[0] = f[a]->x, to[1] = f[a]->y, to[2] = f[a]->z;
    }
  }
  return out;
}

}  // namespace

TEST_CASE("Partner shares kept in a ring give the numbers of shares kept per entry, bit for bit, however small the ring",
          "[dem][contact][ring]") {
  const testing::ParallelEverything every_loop_parallel;
  const testing::PassOneLoop beyond_the_caches(true);  // the loop that keeps rings, on a small bed
  const RollingModel model = GENERATE(RollingModel::constant_torque, RollingModel::epsd);
  // 1,440 barley spheres falling into a box; the bed is still settling after 600 steps (contacts
  // made and broken, list builds), and the last 300 are compared.
  Simulation poured = [&] {
    const RingSize none(0);
    omp_set_num_threads(1);
    Simulation sim = testing::barley_box(model, 12, 12, 10, 42);
    sim.run_steps(600);
    return sim;
  }();
  auto run = [&](std::size_t ring, int threads) {
    const RingSize size(ring);
    omp_set_num_threads(threads);
    Simulation sim = poured;
    sim.run_steps(300);
    omp_set_num_threads(2);
    if (ring > 0) {  // the rings were used, and the array too
      const NeighborList& nl = sim.neighbors();
      const std::uint32_t reach = sim.force_field().share_ring_reach();
      std::uint32_t widest = 0;
      for (std::uint32_t k = 0; k < nl.entries(); ++k) widest = std::max(widest, nl.partners()[k] - nl.owners()[k]);
      INFO("ring of " << ring << " entries: pairs reaching up to " << reach << " slots keep their shares there, of "
                      << widest << "; " << nl.entries() << " entries");
      CHECK(sim.force_field().share_ring_size() == ring);
      CHECK(reach > 0);
      if (ring < 1024) CHECK(reach < widest);  // the smallest ring leaves the widest pairs to the array
    }
    return state(sim);
  };
  const std::vector<double> expected = run(0, 1);
  REQUIRE(expected.size() == 1440 * 15);
  const std::size_t ring = GENERATE(std::size_t{0}, std::size_t{256}, std::size_t{8192});
  const int threads = GENERATE(1, 2, 3);
  INFO(threads << " thread(s), rings of " << ring << " entries");
  const std::vector<double> got = run(ring, threads);
  REQUIRE(got.size() == expected.size());
  CHECK(std::memcmp(got.data(), expected.data(), got.size() * sizeof(double)) == 0);
}

TEST_CASE("A ring too small for one sphere's entries is left unused, with the same numbers", "[dem][contact][ring]") {
  // A big sphere with 150 small ones pressed onto it owns 150 entries, more than half a ring of 256
  // holds: no pair's share can be kept there until it is read, so the ring's reach is 0 and the
  // shares all go to the array (with a reach of 0 the guard would evaluate the batch early for
  // nothing). Forces and torques as with no ring.
  const testing::ParallelEverything every_loop_parallel;
  const testing::PassOneLoop beyond_the_caches(true);
  MaterialTable materials;
  const int m = materials.add({"grain", 1380, 2.6e6, 0.3});
  materials.set_pair(m, m, {0.5, 0.35, 0.08, true});
  std::mt19937_64 rng(11);
  Particles p = testing::big_sphere_pressed(m, 150, rng);
  NeighborList nl;
  testing::build_list(nl, p, 0.0005);
  REQUIRE(nl.end(0) - nl.begin(0) == 150);
  const std::vector<Wall> walls;
  auto forces = [&](std::size_t ring, int threads) {
    const RingSize size(ring);
    omp_set_num_threads(threads);
    Particles q = p;
    NeighborList l = nl;
    ForceField ff;
    ff.setup(materials, walls, RollingSettings{});
    ff.compute(q, l, walls, 1e-6);
    omp_set_num_threads(2);
    if (ring == 256) {
      CHECK(ff.share_ring_size() == 256);
      CHECK(ff.share_ring_reach() == 0);
    }
    if (ring == 8192) CHECK(ff.share_ring_reach() > 0);
    std::vector<Vec3> out(q.force);
    out.insert(out.end(), q.torque.begin(), q.torque.end());
    return out;
  };
  const std::vector<Vec3> expected = forces(0, 1);
  const int threads = GENERATE(1, 2);
  for (const std::size_t ring : {std::size_t{256}, std::size_t{8192}}) {
    INFO("ring of " << ring << " entries, " << threads << " thread(s)");
    const std::vector<Vec3> got = forces(ring, threads);
    CHECK(std::memcmp(got.data(), expected.data(), got.size() * sizeof(Vec3)) == 0);
  }
}
