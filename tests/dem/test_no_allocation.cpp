// "No allocation in the time-step loop": once the buffers have grown to size, stepping - including
// neighbour-list rebuilds and particle reordering - must not touch the heap. Counted by replacing the
// global operator new for this test binary (counting only while a flag is set).
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <memory>
#include <new>

#include "dem/random.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/box.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace grainscale::dem;

TEST_CASE("Stepping allocates nothing once the buffers have grown", "[dem][performance]") {
  const RollingModel model = GENERATE(RollingModel::constant_torque, RollingModel::epsd);
  MaterialTable mt;
  mt.add({"grain", 1380, 2.6e6, 0.3});
  mt.add({"perspex", 1190, 7.97e8, 0.38});
  mt.set_pair(0, 0, {0.5, 0.35, 0.08, true});
  mt.set_pair(0, 1, {0.5, 0.25, 0.01, true});
  SimulationSettings st;
  st.rolling.model = model;
  Simulation sim(mt, st);
  Random rng(3);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 6; ++k)
        sim.add_sphere(0, 0.003, {0.005 + 0.007 * i, 0.005 + 0.007 * j, 0.005 + 0.007 * k},
                       {0.2 * (rng.uniform() - 0.5), 0.2 * (rng.uniform() - 0.5), 0});
  sim.add_wall("box", std::make_shared<BoxGeometry>(Vec3{0, 0, 0}, Vec3{0.075, 0.075, 0.2}), 1);
  sim.run_steps(3000);  // warm-up: the bed falls, settles, buffers reach their size
  const auto builds = sim.neighbors().builds();
  g_allocations = 0;
  g_counting = true;
  sim.run_steps(2000);
  g_counting = false;
  INFO("neighbour-list builds during the counted steps: " << sim.neighbors().builds() - builds);
  CHECK(sim.neighbors().builds() > builds);  // rebuilds happened while counting
  CHECK(g_allocations.load() == 0);
}
