// The split of the force loop's blocks among threads (dem/work_split.hpp): contiguous ranges that
// cover every block once, each thread's cost its share of the total within one block's cost; and the
// feedback: a thread measured slower gets less, in proportion to its speed, while a balanced team is
// left as it is. (That results do not depend on the split is the determinism tests' part: they run
// 1, 2, 3 and 4 threads, each a different split, and require the same bits.)
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "dem/work_split.hpp"

using namespace grainscale::dem;

namespace {

std::vector<double> random_costs(std::size_t blocks, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::vector<double> c(blocks);
  for (double& x : c) x = u(rng);
  return c;
}

double range_cost(const std::vector<double>& c, std::uint32_t a, std::uint32_t b) {
  return std::accumulate(c.begin() + a, c.begin() + b, 0.0);
}

}  // namespace

TEST_CASE("Each thread's blocks cost its share of the total, within one block", "[dem][threads][split]") {
  const int threads = GENERATE(1, 2, 3, 5);
  const std::size_t blocks = GENERATE(std::size_t{0}, std::size_t{3}, std::size_t{200});
  const std::vector<double> cost = random_costs(blocks, 7u + static_cast<unsigned>(threads));
  // Unequal shares too: a thread measured twice as fast gets twice the cost.
  std::vector<double> shares(threads, 1.0 / threads);
  if (threads == 2) shares = {2.0 / 3.0, 1.0 / 3.0};
  std::vector<std::uint32_t> bounds;
  split_work(cost, shares, bounds);
  REQUIRE(bounds.size() == static_cast<std::size_t>(threads) + 1);
  REQUIRE(bounds.front() == 0);
  REQUIRE(bounds.back() == blocks);
  REQUIRE(std::is_sorted(bounds.begin(), bounds.end()));
  const double total = std::accumulate(cost.begin(), cost.end(), 0.0);
  const double largest = blocks > 0 ? *std::max_element(cost.begin(), cost.end()) : 0.0;
  double before = 0;  // the cost of the threads before t, against their shares
  for (int t = 0; t < threads; ++t) {
    before += range_cost(cost, bounds[t], bounds[t + 1]);
    double wanted = 0;
    for (int u = 0; u <= t; ++u) wanted += shares[u] * total;
    // Each cut is at the block boundary nearest its target: off by at most half a block.
    CHECK(std::abs(before - wanted) <= 0.5 * largest + 1e-9 * total);
  }
}

TEST_CASE("The split follows the threads' measured speeds, and leaves a balanced team alone",
          "[dem][threads][split]") {
  const std::vector<double> cost(1000, 1.0);
  WorkSplit split;
  split.split(cost, 2);
  REQUIRE(split.first(0) == 0);
  REQUIRE(split.last(0) == 500);
  REQUIRE(split.last(1) == 1000);

  auto run_steps = [&](int steps, double seconds_per_cost_0, double seconds_per_cost_1) {
    for (int s = 0; s < steps; ++s) {
      split.report(0, seconds_per_cost_0 * static_cast<double>(split.last(0) - split.first(0)));
      split.report(1, seconds_per_cost_1 * static_cast<double>(split.last(1) - split.first(1)));
      split.step_done();
    }
  };
  SECTION("a thread half as fast gets a third of the blocks") {
    run_steps(4, 1e-6, 2e-6);
    REQUIRE_FALSE(split.rebalance());  // too few steps to judge
    run_steps(60, 1e-6, 2e-6);
    REQUIRE(split.rebalance());
    split.split(cost, 2);
    CHECK(split.last(0) == 667);
    // Now balanced: nothing more to do.
    run_steps(64, 1e-6, 2e-6);
    CHECK_FALSE(split.rebalance());
    CHECK(split.last(0) == 667);
  }
  SECTION("a thread slowed a hundredfold keeps blocks to be measured on") {
    run_steps(64, 1e-6, 1e-4);
    REQUIRE(split.rebalance());
    split.split(cost, 2);
    CHECK(split.last(1) - split.first(1) >= 100);  // at least a quarter of an equal share, 125 blocks
    CHECK(split.last(1) - split.first(1) < 200);
  }
  SECTION("within the tolerance the split stays") {
    run_steps(64, 1e-6, 1.02e-6);
    CHECK_FALSE(split.rebalance());
  }
  SECTION("a new team size starts from equal shares") {
    run_steps(64, 1e-6, 2e-6);
    REQUIRE(split.rebalance());
    split.split(cost, 4);
    CHECK(split.threads() == 4);
    CHECK(split.last(0) == 250);
    CHECK(split.last(2) == 750);
  }
}
