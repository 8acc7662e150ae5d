// "No allocation in the time-step loop": once the buffers have grown to size, stepping - including
// neighbour-list rebuilds and particle reordering - must not touch the heap. Counted by replacing the
// global operator new for this test binary (counting only while a flag is set).
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <memory>
#include <new>

#include "barley_box_fixture.hpp"

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
  Simulation sim = testing::barley_box(model, 10, 10, 6, 3);
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
