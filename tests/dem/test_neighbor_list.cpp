// The cell/Verlet neighbour list against a brute-force O(N^2) search (after Cabana's
// neighbor_unit_test), on 1, 2 and 4 threads, across reordering rebuilds; and the carry-over of
// contact histories to the renumbered list.
#include <omp.h>

#include <catch2/catch.hpp>

#include "parallel_everything.hpp"
#include <algorithm>
#include <random>
#include <stdexcept>
#include <set>
#include <utility>

#include "barley_box_fixture.hpp"
#include "list_fixture.hpp"
#include "dem/neighbor_list.hpp"

using namespace grainscale::dem;

namespace {

using PairSet = std::set<std::pair<std::uint64_t, std::uint64_t>>;

Particles random_particles(std::size_t n, double box, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Particles p;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 0.002 + 0.004 * u(rng);  // polydisperse, 3:1 size ratio
    p.add_sphere(i, 0, r, 1000, {box * u(rng), box * u(rng), 0.3 * box * u(rng)});
  }
  return p;
}

PairSet brute_force(const Particles& p, double skin) {
  PairSet s;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      if (p.body[i] == p.body[j]) continue;  // no pair inside a body
      const double cut = p.radius[i] + p.radius[j] + skin;
      if (norm2(p.x[i] - p.x[j]) < cut * cut) s.insert(std::minmax(p.id[i], p.id[j]));
    }
  return s;
}

PairSet listed(const Particles& p, const NeighborList& nl) {
  PairSet s;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto k = nl.begin(i); k < nl.end(i); ++k) {
      const auto pair = std::minmax(p.id[i], p.id[nl.partner(k)]);
      REQUIRE(s.insert(pair).second);  // each pair exactly once
      REQUIRE(i < nl.partner(k));  // stored under the smaller slot
    }
  return s;
}

/// The random bed with two strays 30 m below it, touching each other (grains thrown out of an open
/// box, falling away together).
Particles bed_and_falling_pair() {
  Particles p = random_particles(2000, 0.15, 5);
  p.add_sphere(5000, 0, 0.004, 1000, {0.07, 0.05, -30.0});
  p.add_sphere(5001, 0, 0.004, 1000, {0.075, 0.05, -30.004});
  return p;
}

}  // namespace

TEST_CASE("Neighbour list equals the brute-force pair list", "[dem][neighbor]") {
  const testing::ParallelEverything guard;  // every loop parallel, however small
  const int threads = GENERATE(1, 2, 4);
  omp_set_num_threads(threads);
  // Loose spheres, or spheres in bodies of three (as clumps' spheres: no pair within a body).
  const bool in_bodies = GENERATE(false, true);
  CAPTURE(threads, in_bodies);
  const double skin = 0.001;
  Particles p = random_particles(2000, 0.15, 3);
  if (in_bodies)
    for (std::size_t i = 0; i < p.size(); ++i) p.body[i] = static_cast<std::uint32_t>(i / 3);
  NeighborList nl;
  testing::build_list(nl, p, skin);
  CHECK(listed(p, nl) == brute_force(p, skin));

  // The reverse index lists every entry exactly once, under its partner.
  std::size_t seen = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto r = nl.rev_begin(i); r < nl.rev_end(i); ++r) {
      CHECK(nl.partner(nl.rev_entry(r)) == i);
      CHECK(nl.rev_owner(r) == i);
      ++seen;
    }
  CHECK(seen == nl.entries());

  // Every entry knows its row (the force loop walks entries): owner(k) = i for k in [begin(i), end(i)).
  std::size_t owned = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto k = nl.begin(i); k < nl.end(i); ++k) owned += nl.owner(k) == i;
  CHECK(owned == nl.entries());

  // Move everything a little, rebuild (reordering the slots), compare again.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> jitter(0, 0.002);
  for (auto& x : p.x) x += Vec3{jitter(rng), jitter(rng), jitter(rng)};
  testing::build_list(nl, p, skin);
  CHECK(listed(p, nl) == brute_force(p, skin));
  omp_set_num_threads(2);
}

TEST_CASE("Neighbour list equals brute force whichever axis is thin or long", "[dem][neighbor]") {
  // Cells are numbered with the axis of fewest cells fastest (neighbor_list.hpp): slabs thin along x,
  // y or z and a rod long along each axis put every permutation of the axes through the build.
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  const Vec3 extent = GENERATE(Vec3{0.03, 0.15, 0.15}, Vec3{0.15, 0.03, 0.15}, Vec3{0.15, 0.15, 0.03},
                               Vec3{0.4, 0.05, 0.03}, Vec3{0.05, 0.4, 0.03}, Vec3{0.03, 0.05, 0.4});
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  Particles p;
  for (std::size_t i = 0; i < 1500; ++i) {
    p.add_sphere(i, 0, 0.002 + 0.004 * u(rng), 1000, {extent.x * u(rng), extent.y * u(rng), extent.z * u(rng)});
  }
  const double skin = 0.001;
  NeighborList nl;
  testing::build_list(nl, p, skin);
  INFO("extent " << extent.x << " x " << extent.y << " x " << extent.z << ", " << threads << " thread(s)");
  CHECK(nl.entries() > 1000);
  CHECK(listed(p, nl) == brute_force(p, skin));
  omp_set_num_threads(2);
}

TEST_CASE("Strays far from the bed neither change the list nor coarsen the cells", "[dem][neighbor]") {
  // Grains thrown out of an open box fall away: 30 m below the bed two of them touch, one is alone
  // 1 km to the side. The list still equals brute force (the strays' pair included), and the cells
  // keep their natural size: widening them to span the strays made a 3,600-sphere run 100x slower.
  const testing::ParallelEverything guard;
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  const double skin = 0.001;
  Particles p = bed_and_falling_pair();
  p.add_sphere(5002, 0, 0.004, 1000, {1000.0, 0.05, 0.02});
  NeighborList nl;
  testing::build_list(nl, p, skin);
  const PairSet pairs = listed(p, nl);
  CHECK(pairs == brute_force(p, skin));
  CHECK(pairs.count({5000, 5001}) == 1);
  double r_max = 0;
  for (std::size_t i = 0; i < p.size(); ++i) r_max = std::max(r_max, p.radius[i]);
  CHECK(nl.cell_size() == 2 * r_max + skin);
  // Moved a little and rebuilt (the strays are now mid-list in slot order): still exact.
  for (std::size_t i = 0; i < p.size(); ++i) p.x[i].z += 1e-4 * static_cast<double>(i % 7);
  testing::build_list(nl, p, skin);
  CHECK(listed(p, nl) == brute_force(p, skin));
}

TEST_CASE("A stray far from everything may move further than skin/2 and the list stays exact", "[dem][neighbor]") {
  // A grain thrown out of an open box and falling away moves more than skin/2 every few steps: with
  // the others' rule it forced a build every step (the off-axis DEM of studies/loop_lever_arm/ ran
  // 10-20x slower after one left the box). Its slack is half its gap to everything else.
  const testing::ParallelEverything guard;
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  const double skin = 0.001;
  Particles p = bed_and_falling_pair();  // the pair touch: no slack
  p.add_sphere(5002, 0, 0.004, 1000, {0.07, 0.05, -10.0});  // alone 10 m below the bed
  NeighborList nl;
  testing::build_list(nl, p, skin);
  const std::vector<double>& slack = nl.slack2();
  REQUIRE(slack.size() == p.size());
  auto slot = [&](std::uint64_t id) {
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.id[i] == id) return i;
    FAIL("no particle " << id);
    return std::size_t{0};
  };
  const std::size_t lone = slot(5002);
  // Its gap: to the bed's lowest particle (z >= 0.002) and to the pair 20 m below, whichever is less.
  const double allow = std::sqrt(slack[lone] + 0.25 * skin * skin);
  CHECK(allow > 4.0);
  CHECK(allow < 5.0);
  CHECK(slack[slot(5000)] == 0);
  CHECK(slack[slot(5001)] == 0);
  for (std::size_t i = 0; i < 2000; ++i) CHECK(slack[slot(i)] == 0);
  // Everyone moves: the bed by up to (just under) skin/2, the lone stray 4 m up towards the bed.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 d{u(rng), u(rng), u(rng)};
    p.x[i] += (0.499 * skin / std::sqrt(norm2(d))) * d;
  }
  p.x[lone] = p.x_at_build[lone] + Vec3{0, 0, 0.999 * allow};
  double moved2 = 0;
  for (std::size_t i = 0; i < p.size(); ++i) moved2 = std::max(moved2, norm2(p.x[i] - p.x_at_build[i]) - slack[i]);
  CHECK_FALSE(nl.stale(p, moved2));
  // Not stale, so every touching pair must be listed.
  const PairSet pairs = listed(p, nl);
  for (const auto& pair : brute_force(p, 0.0)) CHECK(pairs.count(pair) == 1);
  // A little further and the list is stale.
  p.x[lone] = p.x_at_build[lone] + Vec3{0, 0, 1.001 * allow};
  moved2 = 0;
  for (std::size_t i = 0; i < p.size(); ++i) moved2 = std::max(moved2, norm2(p.x[i] - p.x_at_build[i]) - slack[i]);
  CHECK(nl.stale(p, moved2));
  // A bed without strays gets no slack at all (the usual test, bit for bit).
  Particles bed = random_particles(2000, 0.15, 5);
  NeighborList plain;
  testing::build_list(plain, bed, skin);
  CHECK(plain.slack2().empty());
}

TEST_CASE("A grain falling away from the box does not force a list build every step", "[dem][neighbor]") {
  // The small barley bed settling in its open box, once alone and once with a grain thrown out of
  // it, 2 m below and falling at 10 m/s: the grain crosses skin/2 every few steps, yet the builds
  // stay those of the bed, and nothing touches the grain: it falls exactly as z0 + v0 t − g t²/2.
  const testing::ParallelEverything guard;
  const int threads = GENERATE(1, 2);
  omp_set_num_threads(threads);
  Simulation alone = testing::barley_box(RollingModel::constant_torque, 8, 8, 7, 42);
  Simulation thrown = testing::barley_box(RollingModel::constant_torque, 8, 8, 7, 42);
  const double z0 = -2.0, v0 = -10.0;
  thrown.add_sphere(0, 0.003, {0.03, 0.03, z0}, {0, 0, v0});
  const std::uint64_t steps = 3000;
  alone.run_steps(steps);
  thrown.run_steps(steps);
  const double t = thrown.time(), skin = thrown.neighbors().skin();
  INFO("builds: " << alone.neighbors().builds() << " alone, " << thrown.neighbors().builds() << " with the grain; "
       << "the grain moved " << -(v0 * t - 4.905 * t * t) / (0.5 * skin) << " half skins");
  CHECK(-(v0 * t - 4.905 * t * t) > 50 * skin);  // without its slack: a build every few steps
  CHECK(thrown.neighbors().builds() <= alone.neighbors().builds() + 2);
  const Particles& p = thrown.particles();
  for (std::size_t s = 0; s < p.size(); ++s) {
    if (p.x[s].z > -1) continue;
    CHECK(p.x[s].z == Approx(z0 + v0 * t - 0.5 * 9.81 * t * t).epsilon(1e-12));
    CHECK(p.v[s].z == Approx(v0 - 9.81 * t).epsilon(1e-12));
  }
  omp_set_num_threads(2);
}

TEST_CASE("Contact histories follow their pair through reordering rebuilds", "[dem][neighbor]") {
  const double skin = 0.001;
  Particles p = random_particles(1500, 0.12, 9);
  NeighborList nl;
  testing::build_list(nl, p, skin);
  // Tag every history with its pair of ids.
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto k = nl.begin(i); k < nl.end(i); ++k)
      nl.shear(k) = {static_cast<double>(p.id[i]), static_cast<double>(p.id[nl.partner(k)]), 1.0};

  std::mt19937_64 rng(1);
  std::normal_distribution<double> jitter(0, 0.0003);
  for (auto& x : p.x) x += Vec3{jitter(rng), jitter(rng), jitter(rng)};
  const PairSet before = listed(p, nl);
  testing::build_list(nl, p, skin);

  // A pair whose owner changed with the renumbering carries its history negated: the history seen
  // from the other particle.
  std::size_t carried = 0, fresh = 0, turned = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (auto k = nl.begin(i); k < nl.end(i); ++k) {
      const auto pair = std::minmax(p.id[i], p.id[nl.partner(k)]);
      const ContactHistory& h = nl.history(k);
      if (before.count(pair)) {
        const double sign = h.shear.z;
        CHECK(std::abs(sign) == 1.0);
        CHECK(sign * h.shear.x == static_cast<double>(p.id[sign > 0 ? i : nl.partner(k)]));
        CHECK(sign * h.shear.y == static_cast<double>(p.id[sign > 0 ? nl.partner(k) : i]));
        ++carried;
        turned += sign < 0;
      } else {
        CHECK(h.shear.z == 0.0);  // a new pair starts without history
        ++fresh;
      }
    }
  CHECK(carried > 1000);
  CHECK(fresh > 0);
  CHECK(turned > 0);
}

TEST_CASE("A list saved keyed on id is restored keyed on slot, each history seen from its new owner",
          "[dem][neighbor][checkpoint]") {
  // Checkpoints written before 2026-12-05 hold the pair under the particle with the smaller id. The
  // same list written that way and restored must give back the list keyed on slot: the same pairs,
  // each under the smaller slot, with its history (negated twice where the owners differ).
  const double skin = 0.001;
  Particles p = random_particles(1500, 0.12, 11);
  NeighborList nl;
  testing::build_list(nl, p, skin);  // slots now in cell order, ids not
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::uint32_t k = 0; k < nl.entries(); ++k) nl.shear(k) = {u(rng), u(rng), u(rng)}, nl.rolling(k) = {u(rng), u(rng), u(rng)};
  const std::size_t n = p.size();
  // The same list keyed on id.
  std::vector<std::uint32_t> start(n + 1, 0), partner(nl.entries());
  std::vector<ContactHistory> history(nl.entries());
  auto id_owner = [&](std::size_t i, std::uint32_t j) { return p.id[i] < p.id[j] ? i : std::size_t{j}; };
  for (std::size_t i = 0; i < n; ++i)
    for (auto k = nl.begin(i); k < nl.end(i); ++k) ++start[id_owner(i, nl.partner(k)) + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (auto k = nl.begin(i); k < nl.end(i); ++k) {
      const std::uint32_t j = nl.partner(k);
      const bool flip = id_owner(i, j) != i;
      const std::uint32_t e = fill[flip ? j : i]++;
      partner[e] = flip ? static_cast<std::uint32_t>(i) : j;
      history[e] = flip ? ContactHistory{-nl.shear(k), -nl.rolling(k)} : nl.history(k);
      moved += flip;
    }
  REQUIRE(moved > 100);  // many pairs have their smaller id at the larger slot
  NeighborList restored;
  restored.restore(p, skin, {}, start, partner, history, 1);
  REQUIRE(restored.entries() == nl.entries());
  REQUIRE(restored.starts() == nl.starts());  // every row holds the same pairs
  for (std::size_t i = 0; i < n; ++i)
    for (auto k = restored.begin(i); k < restored.end(i); ++k) {
      REQUIRE(i < restored.partner(k));
      // The row's pairs, found in the original row (the order within a row may differ).
      auto m = nl.begin(i);
      while (m < nl.end(i) && nl.partner(m) != restored.partner(k)) ++m;
      REQUIRE(m < nl.end(i));
      CHECK(restored.history(k).shear == nl.shear(m));
      CHECK(restored.history(k).rolling == nl.rolling(m));
    }
  // A list keyed on neither (a pair of one particle with itself) is refused.
  partner[0] = static_cast<std::uint32_t>(std::upper_bound(start.begin(), start.end(), 0u) - start.begin() - 1);
  NeighborList refused;
  CHECK_THROWS_AS(refused.restore(p, skin, {}, start, partner, history, 1), std::invalid_argument);
}

namespace {

/// Pairs within r_a + r_b + (s_a + s_b)/2, each particle's skin s given by its id.
template <class SkinOf>
PairSet brute_force_own_skins(const Particles& p, SkinOf skin_of) {
  PairSet s;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double cut = p.radius[i] + p.radius[j] + 0.5 * (skin_of(p.id[i]) + skin_of(p.id[j]));
      if (norm2(p.x[i] - p.x[j]) < cut * cut) s.insert(std::minmax(p.id[i], p.id[j]));
    }
  return s;
}

/// Builds `nl` the way Simulation::rebuild does with a skin per particle (by id), the cells sorted
/// for the largest; returns the skins in the new slot order.
template <class SkinOf>
std::vector<double> build_with_own_skins(NeighborList& nl, Particles& p, double largest, SkinOf skin_of) {
  const auto order = nl.sort_by_cell(p, largest);
  p.permute(order);
  std::vector<double> skins(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) skins[i] = skin_of(p.id[i]);
  nl.build(p, skins, order);
  return skins;
}

}  // namespace

TEST_CASE("With a skin per particle the list equals brute force at (s_a + s_b)/2, and stays exact while each "
          "particle keeps within half its own", "[dem][neighbor][skin]") {
  // dem/adaptive_skin.hpp gives the few fast spheres of a bed skins of their own: one in 50 here,
  // five times the common skin.
  const testing::ParallelEverything guard;
  const int threads = GENERATE(1, 2, 4);
  omp_set_num_threads(threads);
  const double thin = 0.0002, thick = 0.001;
  auto skin_of = [&](std::uint64_t id) { return id % 50 == 7 ? thick : thin; };
  Particles p = random_particles(2000, 0.15, 7);
  NeighborList nl;
  const std::vector<double> skins = build_with_own_skins(nl, p, thick, skin_of);
  INFO(threads << " thread(s), " << nl.entries() << " entries");
  CHECK(listed(p, nl) == brute_force_own_skins(p, skin_of));
  CHECK(nl.skin() == thick);
  CHECK(nl.smallest_skin() == thin);
  CHECK(nl.skins() == skins);
  // Fewer entries than one thick skin for all, more than one thin one.
  CHECK(brute_force(p, thin).size() < nl.entries());
  CHECK(nl.entries() < brute_force(p, thick).size());

  // Each particle moves just under half its own skin: not stale, and every touching pair is listed.
  const std::vector<double>& slack = nl.slack2();
  REQUIRE(slack.size() == p.size());
  auto moved2 = [&] {
    double m = 0;
    for (std::size_t i = 0; i < p.size(); ++i) m = std::max(m, norm2(p.x[i] - p.x_at_build[i]) - slack[i]);
    return m;
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 d{u(rng), u(rng), u(rng)};
    p.x[i] += (0.499 * skins[i] / std::sqrt(norm2(d))) * d;
  }
  CHECK_FALSE(nl.stale(p, moved2()));
  const PairSet pairs = listed(p, nl);
  const PairSet touching = brute_force(p, 0.0);
  REQUIRE(touching.size() > 100);
  for (const auto& pair : touching) CHECK(pairs.count(pair) == 1);
  // One thin-skinned particle a little beyond half its own skin (a fifth of half the thick one):
  // stale.
  std::size_t slot = 0;
  while (skins[slot] != thin) ++slot;
  p.x[slot] = p.x_at_build[slot] + Vec3{0.501 * thin, 0, 0};
  CHECK(nl.stale(p, moved2()));

  // Skins all alike: the list of one skin for all, bit for bit, with no slack.
  Particles q = random_particles(2000, 0.15, 7), r = q;
  NeighborList one, alike;
  testing::build_list(one, q, thin);
  build_with_own_skins(alike, r, thin, [&](std::uint64_t) { return thin; });
  CHECK(alike.starts() == one.starts());
  CHECK(alike.partners() == one.partners());
  CHECK(alike.skins().empty());
  CHECK(alike.slack2().empty());
  CHECK(alike.skin() == thin);
  CHECK(alike.smallest_skin() == thin);
  omp_set_num_threads(2);
}

TEST_CASE("A stray keeps its slack among particles of skins of their own", "[dem][neighbor][skin]") {
  // The stray rule with a skin per particle (NeighborList::assign_stray_slack): the lone grain 10 m
  // below may still move most of its gap; the others' slack is their own skin's.
  const double thin = 0.0002, thick = 0.001;
  auto skin_of = [&](std::uint64_t id) { return id % 50 == 7 ? thick : thin; };
  Particles p = bed_and_falling_pair();
  p.add_sphere(5002, 0, 0.004, 1000, {0.07, 0.05, -10.0});
  // Two more strays 20 m below, 0.5 mm apart: more than their thin skins, less than the thick one.
  // Their gap bounds how far they may move only where it is at least the thick skin (the neighbour
  // beside a stray may hold it): so each may move half its own skin, not half the gap.
  p.add_sphere(5003, 0, 0.004, 1000, {0.07, 0.05, -20.0});
  p.add_sphere(5004, 0, 0.004, 1000, {0.0785, 0.05, -20.0});
  NeighborList nl;
  const std::vector<double> skins = build_with_own_skins(nl, p, thick, skin_of);
  CHECK(listed(p, nl) == brute_force_own_skins(p, skin_of));
  const std::vector<double>& slack = nl.slack2();
  REQUIRE(slack.size() == p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double allow = std::sqrt(slack[i] + 0.25 * thick * thick);
    if (p.id[i] == 5002) {
      CHECK(allow > 4.0);
      CHECK(allow < 5.0);
    } else {
      CHECK(allow == Approx(0.5 * skins[i]).epsilon(1e-12));
    }
  }
}

TEST_CASE("A fast particle's skin reaches the particles of its own and the adjacent cells", "[dem][neighbor][skin]") {
  const double thin = 0.0002, thick = 0.001;
  Particles p = random_particles(2000, 0.15, 9);
  NeighborList nl;
  const auto order = nl.sort_by_cell(p, thick);
  p.permute(order);
  std::vector<double> own(p.size(), thin), out;
  for (std::size_t i = 0; i < p.size(); ++i) own[i] = p.id[i] % 400 == 3 ? thick : thin;
  nl.spread_to_adjacent_cells(p, own, thin, out);
  // Within a cell edge on every axis: the same or an adjacent cell. Two edges away on some axis from
  // every fast particle: no adjacent cell holds one.
  const double c = nl.cell_size();
  std::size_t reached = 0, apart = 0;
  for (std::size_t j = 0; j < p.size(); ++j) {
    bool near = false, far = true;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (own[i] != thick) continue;
      const Vec3 d = p.x[j] - p.x[i];
      const double m = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
      near = near || m < c;
      far = far && m >= 2 * c;
    }
    if (near) {
      CHECK(out[j] == thick);
      ++reached;
    }
    if (far) {
      CHECK(out[j] == thin);
      ++apart;
    }
  }
  INFO(reached << " particles reached, " << apart << " apart");
  CHECK(reached > 10);
  CHECK(apart > 500);
}

TEST_CASE("A list's skins are refused on restore unless one per row, each in [0, the largest]", "[dem][neighbor][skin]") {
  const double thin = 0.0002, thick = 0.001;
  auto skin_of = [&](std::uint64_t id) { return id % 50 == 7 ? thick : thin; };
  Particles p = random_particles(500, 0.08, 13);
  NeighborList nl;
  const std::vector<double> skins = build_with_own_skins(nl, p, thick, skin_of);
  std::vector<ContactHistory> history(nl.entries());
  NeighborList restored;
  restored.restore(p, thick, skins, nl.starts(), nl.partners(), history, 1);
  CHECK(restored.skins() == nl.skins());
  CHECK(restored.slack2() == nl.slack2());
  CHECK(restored.smallest_skin() == thin);
  auto refused = [&](std::vector<double> s, const char* why) {
    INFO(why);
    NeighborList r;
    CHECK_THROWS_AS(r.restore(p, thick, std::move(s), nl.starts(), nl.partners(), history, 1), std::invalid_argument);
  };
  refused(std::vector<double>(skins.begin(), skins.end() - 1), "one short");
  std::vector<double> s = skins;
  s[3] = 2 * thick;
  refused(s, "beyond the largest");
  s[3] = -thin;
  refused(s, "negative");
  s[3] = std::nan("");
  refused(s, "not a number");
}
