// The wall-contact slots (dem/wall_slots.hpp): the slots in use survive growing, shrinking,
// renumbering, copying and the step's flip, checked against a plain list per sphere; and the slots no
// sphere uses are never written, so their pages never become resident (mincore), which is what keeps
// a bed's memory at a third of what 2 x 8 slots per sphere would cost.
#include <sys/mman.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <numeric>
#include <random>
#include <vector>

#include "dem/wall_slots.hpp"

using namespace grainscale::dem;

namespace {

using Reference = std::vector<std::vector<WallSlot>>;  // per sphere, its slots in use

WallSlot slot_for(std::size_t i, int s) {
  WallSlot w;
  w.wall = static_cast<std::int32_t>(s);
  w.feature = static_cast<std::int32_t>(i);
  w.history.shear = {1.0 * i, 2.0 * s, 3.0};
  w.history.rolling = {-1.0 * i, 0.5 * s, 7.0};
  return w;
}

bool same(const WallSlot& a, const WallSlot& b) {
  return a.wall == b.wall && a.feature == b.feature && a.history.shear.x == b.history.shear.x &&
         a.history.shear.y == b.history.shear.y && a.history.rolling.x == b.history.rolling.x &&
         a.history.rolling.y == b.history.rolling.y && a.history.rolling.z == b.history.rolling.z;
}

void require_matches(const WallSlots& w, const Reference& ref) {
  REQUIRE(w.stride() == ref.size());
  for (std::size_t i = 0; i < ref.size(); ++i) {
    REQUIRE(w.counts_vector()[i] == ref[i].size());
    for (int s = 0; s < static_cast<int>(ref[i].size()); ++s) REQUIRE(same(w.now(i, s), ref[i][s]));
  }
}

/// Random counts 0..kSlots (mostly 0 or 1, as in a bed) and distinct slots.
Reference random_reference(std::size_t n, std::mt19937& rng) {
  Reference ref(n);
  std::uniform_int_distribution<int> pick(0, 19);
  for (std::size_t i = 0; i < n; ++i) {
    const int r = pick(rng);
    const int count = r < 10 ? 0 : r < 17 ? 1 : r - 17 + 2 + (r == 19 ? 4 : 0);  // 0, 1, 2, 3, 8
    for (int s = 0; s < std::min(count, WallSlots::kSlots); ++s) ref[i].push_back(slot_for(i, s));
  }
  return ref;
}

WallSlots from_reference(const Reference& ref) {
  std::vector<std::uint8_t> counts;
  std::vector<WallSlot> used;
  for (const auto& r : ref) {
    counts.push_back(static_cast<std::uint8_t>(r.size()));
    used.insert(used.end(), r.begin(), r.end());
  }
  WallSlots w;
  w.assign(counts, used);
  return w;
}

}  // namespace

TEST_CASE("Wall slots in use survive growing, shrinking, renumbering and copying", "[dem][walls][memory]") {
  std::mt19937 rng(7);
  Reference ref = random_reference(300, rng);
  WallSlots w = from_reference(ref);
  require_matches(w, ref);

  w.resize(340);  // spheres added: no contacts yet
  ref.resize(340);
  require_matches(w, ref);

  std::vector<std::uint32_t> order(340);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), rng);
  w.permute(order);
  Reference renumbered(340);
  for (std::size_t i = 0; i < order.size(); ++i) renumbered[i] = ref[order[i]];
  require_matches(w, renumbered);

  const WallSlots copy(w);  // a deep copy, independent of the original
  WallSlots assigned = from_reference(random_reference(17, rng));
  assigned = w;
  WallSlots moved(std::move(w));  // the original's slots, now here
  require_matches(moved, renumbered);
  std::reverse(order.begin(), order.end());
  moved.permute(order);  // rewrites them: the copies must not see it
  require_matches(copy, renumbered);
  require_matches(assigned, renumbered);

  REQUIRE(w.stride() == 0);  // a moved-from one is empty and usable
  w.resize(3);
  REQUIRE(w.counts_vector() == std::vector<std::uint8_t>(3, 0));

  assigned.resize(250);  // spheres dropped from the end
  renumbered.resize(250);
  require_matches(assigned, renumbered);

  // A step's flip: this step's slots become last step's, read through before().
  assigned.flip();
  for (std::size_t i = 0; i < renumbered.size(); ++i) {
    REQUIRE(assigned.before_counts()[i] == renumbered[i].size());
    for (std::size_t s = 0; s < renumbered[i].size(); ++s) {
      REQUIRE(same(assigned.before(i)[s * assigned.stride()], renumbered[i][s]));
    }
  }
}

TEST_CASE("Wall slots no sphere uses never become resident memory", "[dem][walls][memory]") {
  // 10^5 spheres on a floor: slot 0 in use for a third of them, the other seven slots for none.
  const std::size_t n = 100000;
  Reference ref(n);
  for (std::size_t i = 0; i < n; i += 3) ref[i].push_back(slot_for(i, 0));
  const WallSlots original = from_reference(ref);
  WallSlots grown(original);
  grown.resize(n + 1000);
  std::vector<std::uint32_t> order(n + 1000);
  std::iota(order.rbegin(), order.rend(), 0u);
  grown.permute(order);

  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  auto resident_pages = [&](const WallSlot* from, const WallSlot* to) {
    const auto lo = (reinterpret_cast<std::uintptr_t>(from) + page - 1) / page * page;
    const auto hi = reinterpret_cast<std::uintptr_t>(to) / page * page;
    if (hi <= lo) return std::size_t{0};
    std::vector<unsigned char> in_core((hi - lo) / page);
    REQUIRE(mincore(reinterpret_cast<void*>(lo), hi - lo, in_core.data()) == 0);
    return static_cast<std::size_t>(std::count_if(in_core.begin(), in_core.end(), [](unsigned char c) { return c & 1; }));
  };
  for (const WallSlots* w : std::initializer_list<const WallSlots*>{&original, &grown}) {
    const WallSlot* base = w->now(0);
    const std::size_t stride = w->stride();
    INFO("stride " << stride);
    // slot 0 is written, slots 1..7 (7 x ~5.6 MB) are not
    REQUIRE(resident_pages(base, base + stride) > 0);
    REQUIRE(resident_pages(base + stride, base + WallSlots::kSlots * stride) == 0);
  }
}
