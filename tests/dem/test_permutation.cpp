// Renumbering arrays with the spheres (dem/permutation.hpp): new slot i takes what old slot
// new_to_old[i] held. A build in a bed at rest moves few slots, in runs (a sphere that changes cell
// shifts the slots between its old and new place by one), and then only those are copied; the
// arrays must end up as the definition has them, element for element, whichever way is taken.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "dem/bodies.hpp"
#include "dem/particles.hpp"
#include "dem/permutation.hpp"
#include "dem/wall_slots.hpp"

using namespace grainscale::dem;

namespace {

/// The sphere at slot `from` moves to slot `to` (a cell change in sorted order): the slots between
/// shift by one towards `from`.
void move_one(std::vector<std::uint32_t>& order, std::size_t from, std::size_t to) {
  const std::uint32_t s = order[from];
  order.erase(order.begin() + static_cast<std::ptrdiff_t>(from));
  order.insert(order.begin() + static_cast<std::ptrdiff_t>(to), s);
}

/// Renumberings of n slots as builds make them: none moved, one sphere's move, a few, a swap, one
/// moving too many slots for the sparse way, and a shuffle.
std::vector<std::uint32_t> renumbering_of_kind(const std::string& kind, std::size_t n) {
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::mt19937 rng(11);
  if (kind == "one sphere moves a row on") move_one(order, 40, 40 + n / 20);
  if (kind == "one sphere moves a row back") move_one(order, 700, 700 - n / 20);
  if (kind == "a few spheres move") {
    for (std::size_t k = 0; k < 6; ++k) move_one(order, 100 + 150 * k, 100 + 150 * k + 7 + k);
  }
  if (kind == "two spheres swap") std::swap(order[3], order[n - 1]);
  if (kind == "a long run shifts") move_one(order, 0, n / 2);  // half the slots: renumbered whole
  if (kind == "a shuffle") std::shuffle(order.begin(), order.end(), rng);
  return order;
}

}  // namespace

TEST_CASE("A renumbering lists the slots it moves, and arrays renumbered by those alone end as the definition has them",
          "[dem][permutation]") {
  const std::size_t n = 1000;
  const std::string kind = GENERATE(as<std::string>{}, "none", "one sphere moves a row on", "one sphere moves a row back",
                                    "a few spheres move", "two spheres swap", "a long run shifts", "a shuffle");
  CAPTURE(kind);
  const std::vector<std::uint32_t> order = renumbering_of_kind(kind, n);
  const Renumbering r(order);
  std::vector<std::uint32_t> moved;
  for (std::uint32_t i = 0; i < n; ++i)
    if (order[i] != i) moved.push_back(i);
  const bool few = moved.size() <= n / Renumbering::kSparseShare;
  REQUIRE(r.sparse() == few);
  REQUIRE(r.moved() == (few ? moved : std::vector<std::uint32_t>{}));
  if (kind == "one sphere moves a row on") REQUIRE(moved.size() == n / 20 + 1);
  if (kind == "a long run shifts" || kind == "a shuffle") REQUIRE_FALSE(r.sparse());

  // The arrays, whichever way they are renumbered.
  std::vector<Vec3> a(n);
  for (std::size_t i = 0; i < n; ++i) a[i] = {1.0 * i, -2.0 * i, 0.5 + i};
  std::vector<Vec3> expected(n);
  for (std::size_t i = 0; i < n; ++i) expected[i] = a[order[i]];
  // A scratch buffer of another size, as an earlier renumbering left it (its contents are not read).
  std::vector<Vec3> scratch(3, Vec3{-7, -7, -7});
  permute_array(a, scratch, r);
  for (std::size_t i = 0; i < n; ++i) {
    INFO("slot " << i);
    REQUIRE(a[i].x == expected[i].x);
    REQUIRE(a[i].y == expected[i].y);
    REQUIRE(a[i].z == expected[i].z);
  }
  // Twice in a row through the same scratch (a build after a build).
  permute_array(a, scratch, r);
  for (std::size_t i = 0; i < n; ++i) REQUIRE(a[i].x == expected[order[i]].x);

  // Every array of the spheres and of the bodies, and the wall slots, the same way.
  Particles p;
  Bodies b;
  for (std::size_t i = 0; i < n; ++i) {
    p.add_sphere(100 + i, static_cast<int>(i % 3), 0.001 * (1 + i % 7), 1000, {0.01 * i, 0, 0}, {0, 0.1 * i, 0});
    b.id.push_back(i), b.shape.push_back(-1), b.mass.push_back(1.0 + i), b.inv_mass.push_back(1 / (1.0 + i));
    b.inertia.push_back({1.0 * i, 1, 1}), b.x.push_back({2.0 * i, 0, 0}), b.v.push_back({}), b.L.push_back({});
    b.omega.push_back({0, 0, 1.0 * i}), b.q.push_back({}), b.force.push_back({}), b.torque.push_back({3.0 * i, 0, 0});
  }
  const Particles p0 = p;
  const Bodies b0 = b;
  p.permute(r);
  b.permute(r);
  for (std::size_t i = 0; i < n; ++i) {
    INFO("slot " << i);
    const std::size_t o = order[i];
    REQUIRE(p.id[i] == p0.id[o]);
    REQUIRE(p.material[i] == p0.material[o]);
    REQUIRE(p.radius[i] == p0.radius[o]);
    REQUIRE(p.mass[i] == p0.mass[o]);
    REQUIRE(p.x[i].x == p0.x[o].x);
    REQUIRE(p.v[i].y == p0.v[o].y);
    REQUIRE(p.x_at_build[i].x == p0.x_at_build[o].x);
    REQUIRE(b.id[i] == b0.id[o]);
    REQUIRE(b.mass[i] == b0.mass[o]);
    REQUIRE(b.inertia[i].x == b0.inertia[o].x);
    REQUIRE(b.omega[i].z == b0.omega[o].z);
    REQUIRE(b.torque[i].x == b0.torque[o].x);
  }

  // Wall slots: sphere i has i % 3 slots in use (0, 1 or 2), each naming its sphere.
  std::vector<std::uint8_t> counts(n);
  std::vector<WallSlot> used;
  for (std::size_t i = 0; i < n; ++i) {
    counts[i] = static_cast<std::uint8_t>(i % 3);
    for (int s = 0; s < counts[i]; ++s) {
      WallSlot w;
      w.wall = s, w.feature = static_cast<std::int32_t>(i), w.history.shear = {1.0 * i, 1.0 * s, 0};
      used.push_back(w);
    }
  }
  WallSlots slots;
  slots.assign(counts, used);
  slots.flip(), slots.flip();  // last step's counts are not zero when a build comes
  slots.permute(r);
  for (std::size_t i = 0; i < n; ++i) {
    INFO("slot " << i);
    REQUIRE(slots.counts()[i] == counts[order[i]]);
    REQUIRE(slots.before_counts()[i] == 0);  // last step's read as none after a renumbering
    for (int s = 0; s < slots.counts()[i]; ++s) {
      REQUIRE(slots.now(i, s).feature == static_cast<std::int32_t>(order[i]));
      REQUIRE(slots.now(i, s).wall == s);
      REQUIRE(slots.now(i, s).history.shear.x == 1.0 * order[i]);
    }
  }
}
