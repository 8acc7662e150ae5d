// Nice ticks: steps of 1, 2 or 5 x 10^k that cover the data with a sensible count, and labels that
// are distinct, equally precise and never "-0".
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "studies/nice_ticks.hpp"

using namespace grainscale::studies;

namespace {
/// The step's leading digit (1, 2 or 5 for a nice step).
int mantissa(double step) { return static_cast<int>(std::lround(step / std::pow(10.0, std::floor(std::log10(step) + 1e-9)))); }
}  // namespace

TEST_CASE("Nice steps are 1, 2 or 5 times a power of ten", "[studies][plot][ticks]") {
  CHECK(nice_step(1.0, 5) == Approx(0.2));
  CHECK(nice_step(0.8, 4) == Approx(0.2));
  CHECK(nice_step(7.0, 5) == Approx(1.0));
  CHECK(nice_step(3e-6, 5) == Approx(5e-7));
  CHECK(nice_step(450.0, 5) == Approx(100.0));
  CHECK_THROWS_AS(nice_step(0.0, 5), std::invalid_argument);
}

TEST_CASE("Ticks from data round outwards to whole steps and label with shared precision", "[studies][plot][ticks]") {
  const Ticks t = nice_ticks(0.13, 0.87, 5);
  CHECK(t.step == Approx(0.2));
  CHECK(t.lo == 0.0);
  CHECK(t.hi == Approx(1.0));
  REQUIRE(t.values.size() == 6);
  CHECK(tick_labels(t) == std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0"});

  CHECK(tick_labels(nice_ticks(-1, 1, 4)) == std::vector<std::string>{"-1.0", "-0.5", "0.0", "0.5", "1.0"});
  CHECK(tick_labels(nice_ticks(0, 800, 4)) == std::vector<std::string>{"0", "200", "400", "600", "800"});
  // Very small numbers share one exponent instead of a row of zeros.
  CHECK(tick_labels(nice_ticks(0, 2e-6, 4)) == std::vector<std::string>{"0", "0.5e-6", "1.0e-6", "1.5e-6", "2.0e-6"});
  CHECK(tick_labels(nice_ticks(0, 3e5, 3)) == std::vector<std::string>{"0", "1e5", "2e5", "3e5"});
  // A single value gets a range around it.
  const Ticks one = nice_ticks(3, 3, 5);
  CHECK(one.lo < 3);
  CHECK(one.hi > 3);
  const Ticks zero = nice_ticks(0, 0, 5);
  CHECK(zero.lo < 0);
  CHECK(zero.hi > 0);
  CHECK_THROWS_AS(nice_ticks(std::nan(""), 1, 5), std::invalid_argument);
  CHECK_THROWS_AS(nice_ticks(2, 1, 5), std::invalid_argument);
}

TEST_CASE("Nice ticks cover any range with a count near the target and distinct labels", "[studies][plot][ticks]") {
  for (double lo : {-3.7e4, -12.0, -0.013, 0.0, 1e-7, 0.2, 17.0}) {
    for (double span : {1e-8, 3.3e-5, 0.0123, 0.7, 1.0, 9.99, 250.0, 6e4}) {
      for (int target : {3, 5, 8}) {
        if (span < 1e-6 * std::abs(lo)) continue;  // beyond double precision's reach, not a plot
        const double hi = lo + span;
        const Ticks t = nice_ticks(lo, hi, target);
        INFO("range [" << lo << ", " << hi << "], target " << target << ", step " << t.step);
        const int m = mantissa(t.step);
        CHECK((m == 1 || m == 2 || m == 5 || m == 10));
        CHECK(t.lo <= lo);
        CHECK(t.hi >= hi);
        const double intervals = (t.hi - t.lo) / t.step;
        // Steps round to 1-2-5 on a log scale and the ends round outwards: between about 0.4
        // and 2 times the target count.
        CHECK(intervals >= std::max(2.0, 0.4 * target) - 1e-9);
        CHECK(intervals <= 2.0 * target + 1e-9);
        CHECK(t.values.size() == static_cast<std::size_t>(std::lround(intervals)) + 1);
        const auto labels = tick_labels(t);
        CHECK(std::set<std::string>(labels.begin(), labels.end()).size() == labels.size());
        for (const auto& s : labels) CHECK(s != "-0");
      }
    }
  }
}

TEST_CASE("Ticks within a fixed range stay inside it", "[studies][plot][ticks]") {
  const Ticks t = ticks_within(0.03, 0.97, 5);
  CHECK(t.lo == 0.03);
  CHECK(t.hi == 0.97);
  REQUIRE(!t.values.empty());
  for (double v : t.values) {
    CHECK(v >= 0.03);
    CHECK(v <= 0.97);
  }
  CHECK(t.values.front() == Approx(0.2));
  CHECK_THROWS_AS(ticks_within(1, 1, 5), std::invalid_argument);
}
