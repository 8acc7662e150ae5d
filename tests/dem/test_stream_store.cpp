// Stores past the caches (dem/stream_store.hpp): the drift's new sphere state, the loose spheres'
// omega and the bodies' sums in beds beyond the caches. They must write exactly what an ordinary
// store writes, at every element's place in its lines, and leave a run the same bit for bit.
#include <omp.h>

#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

#include "barley_box_fixture.hpp"
#include "dem/stream_store.hpp"
#include "parallel_everything.hpp"
#include "pass_one_loop.hpp"

using namespace grainscale::dem;

TEST_CASE("A store past the caches writes its element whole and nothing beside it", "[dem][stream_store]") {
  // 24-byte elements begin at 8 of a line's 64 bytes and straddle two lines in 2 of 8: every place.
  constexpr std::size_t n = 64;
  const Vec3 old{-1.5, -2.5, -3.5};
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<Vec3> a(n, old);
    const Vec3 v{1.0 + static_cast<double>(i), -0.0, 1e-300 * static_cast<double>(i + 1)};
    stream_store(&a[i], v);
    stream_fence();
    INFO("element " << i);
    CHECK(std::memcmp(&a[i], &v, sizeof v) == 0);  // bit for bit, the sign of -0 included
    for (std::size_t j = 0; j < n; ++j) {
      if (j != i) REQUIRE(std::memcmp(&a[j], &old, sizeof old) == 0);
    }
  }
}

TEST_CASE("Loose spheres move the same, bit for bit, with the step's stores past the caches or not",
          "[dem][stream_store][determinism]") {
  // The loop of beds beyond the caches (beyond_cache_spheres 0) stores the drift's sphere state,
  // the loose bodies' omega and the bodies' sums past the caches; the loop of beds within them does
  // not, and the two loops give the same numbers. A component lost, or a store to the wrong place,
  // shows in the state (the 1,440 spheres fall, collide and settle: 2,000 steps).
  const testing::ParallelEverything guard;  // every loop parallel, however small
  auto run = [](int threads, bool beyond_the_caches) {
    const testing::PassOneLoop loop(beyond_the_caches);
    omp_set_num_threads(threads);
    Simulation sim = testing::barley_box(RollingModel::constant_torque, 12, 12, 10, 7);
    sim.run_steps(2000);
    omp_set_num_threads(2);
    const Particles& p = sim.particles();
    std::vector<Vec3> state(p.size() * 4);
    for (std::size_t s = 0; s < p.size(); ++s) {  // by id: the slots are the list's order
      const std::size_t i = p.id[s] * 4;
      state[i] = p.x[s], state[i + 1] = p.v[s], state[i + 2] = p.omega[s];
      state[i + 3] = sim.bodies().force[p.body[s]];
    }
    return state;
  };
  testing::check_same_beyond_the_caches(run, 2);
}
