// Same input -> bitwise-identical trajectory, on 1 and on 2 threads. Forces are accumulated per
// particle in a fixed order (dem/force_field.hpp), so the thread count cannot change the sums.
#include <omp.h>

#include <catch2/catch.hpp>

#include "parallel_everything.hpp"
#include "pass_one_loop.hpp"
#include <cstring>
#include <memory>
#include <vector>

#include "barley_box_fixture.hpp"

using namespace grainscale::dem;

namespace {

std::vector<double> settle(int threads, RollingModel model) {
  omp_set_num_threads(threads);
  // 1,440 spheres, 23 blocks of the force loop: enough that the chunked loop's block prefetch (8
  // blocks ahead, dem/force_field.cpp) runs in both threads' ranges.
  Simulation sim = testing::barley_box(model, 12, 12, 10, 42);
  sim.run_steps(3000);
  // State sorted by id.
  const Particles& p = sim.particles();
  std::vector<double> out(p.size() * 9);
  for (std::size_t s = 0; s < p.size(); ++s) {
    const std::size_t i = p.id[s] * 9;
    const Vec3* f[3] = {&p.x[s], &p.v[s], &p.omega[s]};
    for (int a = 0; a < 3; ++a) {
      out[i + 3 * a] = f[a]->x, out[i + 3 * a + 1] = f[a]->y, out[i + 3 * a + 2] = f[a]->z;
    }
  }
  omp_set_num_threads(2);
  return out;
}

}  // namespace

TEST_CASE("A run is bitwise identical on 1 and 2 threads", "[dem][determinism]") {
  const testing::ParallelEverything guard;  // every loop parallel, however small
  const RollingModel model = GENERATE(RollingModel::constant_torque, RollingModel::epsd);
  // Both of pass 1's entry loops (the chunked one is taken by beds beyond the caches).
  const bool chunked = GENERATE(false, true);
  INFO("pass 1's " << (chunked ? "chunked" : "entry-by-entry") << " loop");
  const testing::PassOneLoop loop(chunked);
  const auto one = settle(1, model);
  const auto two = settle(2, model);
  REQUIRE(one.size() == two.size());
  CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)) == 0);
  CHECK(settle(2, model) == two);  // and repeatable
}
