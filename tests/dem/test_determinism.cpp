// Same input -> bitwise-identical trajectory, on 1 and on 2 threads. Forces are accumulated per
// particle in a fixed order (dem/force_field.hpp), so the thread count cannot change the sums.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "dem/simulation.hpp"
#include "dem/walls/box.hpp"

using namespace grainscale::dem;

namespace {

std::vector<double> settle(int threads, RollingModel model) {
  omp_set_num_threads(threads);
  MaterialTable mt;
  mt.add({"grain", 1380, 2.6e6, 0.3});
  mt.add({"perspex", 1190, 7.97e8, 0.38});
  mt.set_pair(0, 0, {0.5, 0.35, 0.08, true});
  mt.set_pair(0, 1, {0.5, 0.25, 0.01, true});
  SimulationSettings st;
  st.rolling.model = model;
  Simulation sim(mt, st);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 8; ++i)  // jittered lattice, spacing 7 mm > largest diameter 6.6 mm
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 7; ++k) {
        const Vec3 x{0.005 + 0.007 * i, 0.005 + 0.007 * j, 0.005 + 0.007 * k};
        sim.add_sphere(0, 0.003 * (1 + 0.1 * u(rng)), x + Vec3{2e-4 * u(rng), 2e-4 * u(rng), 0}, {0.1 * u(rng), 0, 0});
      }
  sim.add_wall("box", std::make_shared<BoxGeometry>(Vec3{0, 0, 0}, Vec3{0.06, 0.06, 0.2}), 1);
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
  const RollingModel model = GENERATE(RollingModel::constant_torque, RollingModel::epsd);
  const auto one = settle(1, model);
  const auto two = settle(2, model);
  REQUIRE(one.size() == two.size());
  CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)) == 0);
  CHECK(settle(2, model) == two);  // and repeatable
}
