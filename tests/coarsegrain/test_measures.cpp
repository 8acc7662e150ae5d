// The report's measures on synthetic layouts with known answers: chaff per 50 mm slice (Figure 11),
// top-view chaff coverage, and the congregation index.
#include <catch2/catch.hpp>
#include <cmath>

#include "coarsegrain/congregation_index.hpp"
#include "coarsegrain/slice_histogram.hpp"
#include "coarsegrain/top_view.hpp"
#include "synthetic_snapshot.hpp"

using namespace grainscale;
using namespace grainscale::cg;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

constexpr double kLength = 0.8, kWidth = 0.2;
const Vec3 kLo{0, 0, 0}, kHi{kLength, kWidth, 0.2};

CgParticles particles(const dem::Snapshot& s, const SpeciesTable& t) { return container_particles(s, {}, t); }

/// One layer of touching spheres (radius 2.5 mm, centres on a 5 mm square lattice) covering the
/// floor, at height z; `is_chaff(x, y)` picks the species (material 1 = chaff, 0 = wheat).
template <class Pick>
void add_layer(dem::Snapshot& s, double z, Pick is_chaff) {
  const double r = 0.0025, a = 0.005;
  for (int j = 0; j < static_cast<int>(std::lround(kWidth / a)); ++j)
    for (int i = 0; i < static_cast<int>(std::lround(kLength / a)); ++i) {
      const Vec3 x{(i + 0.5) * a, (j + 0.5) * a, z};
      const bool chaff = is_chaff(x);
      test::add_sphere(s, chaff ? 1 : 0, r, chaff ? 100 : 1380, x);
    }
}

}  // namespace

TEST_CASE("Slice histogram: chaff per 50 mm slice as a percentage of all chaff, and per-slice fractions", "[cg][measures]") {
  dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
  const Slices slices(0, kLength, 0.05);
  REQUIRE(slices.count() == 16);
  // 10 grains in every slice; s % 4 loose chaff spheres in slice s (total 24).
  double want_chaff[16];
  for (int sl = 0; sl < 16; ++sl) {
    for (int g = 0; g < 10; ++g) test::add_sphere(s, 0, 0.002, 1380, {slices.lower(sl) + 0.004 * (g + 1), 0.1, 0.02});
    want_chaff[sl] = sl % 4;
    for (int c = 0; c < sl % 4; ++c) test::add_sphere(s, 1, 0.002, 100, {slices.lower(sl) + 0.01 * (c + 1), 0.05, 0.03});
  }
  // A chaff flake of two spheres whose centre of mass is in slice 2 (x = 0.1499) but whose second
  // sphere lies in slice 3: one particle, counted in slice 2; its volume split between the two.
  test::add_clump(s, 1, 100, {{{0.1449, 0.1, 0.04}, 0.002}, {{0.1549, 0.1, 0.04}, 0.002}}, {0.1499, 0.1, 0.04});
  want_chaff[2] += 1;
  const SpeciesTable species = species_from_snapshot(s, {"chaff"});
  const SliceHistogram h = slice_histogram(particles(s, species), species, slices);
  CHECK(h.chaff_total == 25);
  CHECK(h.grain_total == 160);
  CHECK(h.outside == 0);
  double percent_sum = 0;
  for (int sl = 0; sl < 16; ++sl) {
    CAPTURE(sl);
    const auto k = static_cast<std::size_t>(sl);
    CHECK(h.chaff_bodies[k] == want_chaff[sl]);
    CHECK(h.grain_bodies[k] == 10);
    CHECK_THAT(h.chaff_percent[k], WithinRel(100.0 * want_chaff[sl] / 25, 1e-15));
    CHECK_THAT(h.chaff_number_fraction[k], WithinRel(want_chaff[sl] / (want_chaff[sl] + 10), 1e-15));
    percent_sum += h.chaff_percent[k];
  }
  CHECK_THAT(percent_sum, WithinRel(100.0, 1e-14));
  // Volume, by sphere centres: all spheres have one radius; slice 2 holds 2 loose chaff spheres and
  // one of the flake's, slice 3 holds 3 and the other.
  CHECK_THAT(h.chaff_volume_fraction[2], WithinRel(3.0 / 13, 1e-14));
  CHECK_THAT(h.chaff_volume_fraction[3], WithinRel(4.0 / 14, 1e-14));
}

TEST_CASE("Top-view coverage of synthetic layouts: all chaff 1, none 0, half 0.5", "[cg][measures]") {
  const TopViewSettings settings{0.001, 0.0};
  const SpeciesTable species{{"wheat", "chaff"}, {false, true}, {}};
  auto view_of = [&](auto pick) {
    dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
    add_layer(s, 0.0025, pick);
    return render_top_view(particles(s, species), species, kLo, kHi, settings);
  };
  SECTION("all chaff") { CHECK(view_of([](const Vec3&) { return true; }).coverage() == 1.0); }
  SECTION("no chaff") { CHECK(view_of([](const Vec3&) { return false; }).coverage() == 0.0); }
  SECTION("alternate rows across the width") {
    const TopView v = view_of([](const Vec3& x) { return std::lround(x.y / 0.005 - 0.5) % 2 == 0; });
    CHECK(v.coverage() == 0.5);
    // Each disc (radius 2.5 pixels, centred on a pixel centre) covers the 21 of its 5 x 5 pixels whose
    // centres are within 2.5 pixels.
    CHECK_THAT(v.occupied_fraction(), WithinRel(21.0 / 25, 1e-15));
  }
  SECTION("chaff in the left half: profile 1 then 0") {
    const TopView v = view_of([](const Vec3& x) { return x.x < 0.4; });
    CHECK(v.coverage() == 0.5);
    const CoverageProfile p = coverage_profile(v, Slices(0, kLength, 0.05));
    REQUIRE(p.coverage.size() == 16);
    for (std::size_t k = 0; k < 16; ++k) CHECK(p.coverage[k] == (k < 8 ? 1.0 : 0.0));
  }
}

TEST_CASE("Top-view coverage sees the top layer only, and buried chaff within a thicker layer", "[cg][measures]") {
  const SpeciesTable species{{"wheat", "chaff"}, {false, true}, {}};
  dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
  add_layer(s, 0.0025, [](const Vec3&) { return true; });    // chaff on the floor
  add_layer(s, 0.0075, [](const Vec3&) { return false; });   // wheat on top, directly above
  const CgParticles p = particles(s, species);
  CHECK(render_top_view(p, species, kLo, kHi, {0.001, 0.0}).coverage() == 0.0);
  // Directly below, each chaff sphere's top is 5 mm (one diameter) under the wheat's.
  CHECK(render_top_view(p, species, kLo, kHi, {0.001, 0.0049}).coverage() == 0.0);
  CHECK(render_top_view(p, species, kLo, kHi, {0.001, 0.0051}).coverage() == 1.0);
}

TEST_CASE("Congregation index: 1 for a uniform mixture, the chaff excess at the ends otherwise", "[cg][measures]") {
  const SpeciesTable species{{"wheat", "chaff"}, {false, true}, {}};
  const Slices slices(0, kLength, 0.05);
  auto bed = [&](auto chaff_in_slice) {
    dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
    for (int sl = 0; sl < 16; ++sl) {
      for (int g = 0; g < 10; ++g) test::add_sphere(s, 0, 0.002, 1380, {slices.lower(sl) + 0.004 * (g + 1), 0.1, 0.02});
      for (int c = 0; c < chaff_in_slice(sl); ++c) test::add_sphere(s, 1, 0.002, 100, {slices.lower(sl) + 0.01 * (c + 1), 0.05, 0.03});
    }
    return particles(s, species);
  };
  const CongregationIndex uniform = congregation_index(bed([](int) { return 2; }), species, 0, kLength, 0.1, nullptr);
  CHECK_THAT(uniform.left, WithinRel(1.0, 1e-15));
  CHECK_THAT(uniform.right, WithinRel(1.0, 1e-15));
  CHECK_THAT(uniform.share_right, WithinRel(1.0, 1e-15));
  CHECK(uniform.spread == 0.0);
  CHECK(std::isnan(uniform.coverage_ratio));
  // Two chaff in each of the four end slices, none elsewhere: c_end = 4/24, c_all = 8/168.
  const CongregationIndex ends = congregation_index(bed([](int sl) { return sl < 2 || sl > 13 ? 2 : 0; }), species, 0, kLength, 0.1, nullptr);
  CHECK_THAT(ends.left, WithinRel((4.0 / 24) / (8.0 / 168), 1e-15));
  CHECK_THAT(ends.mean, WithinRel(3.5, 1e-15));
  CHECK_THAT(ends.share_left, WithinRel(0.5 / 0.125, 1e-15));
  // More at the right end: positive spread.
  const CongregationIndex right = congregation_index(bed([](int sl) { return sl > 13 ? 3 : 1; }), species, 0, kLength, 0.1, nullptr);
  CHECK(right.spread > 0);
  CHECK_THROWS(congregation_index(bed([](int) { return 1; }), species, 0, kLength, 0.5, nullptr));

  // Coverage ratio: ends fully chaff, the central 100 mm half chaff (alternate rows): 1 / 0.5 = 2.
  dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
  add_layer(s, 0.0025, [](const Vec3& x) {
    if (x.x < 0.1 || x.x > 0.7) return true;
    if (x.x > 0.35 && x.x < 0.45) return std::lround(x.y / 0.005 - 0.5) % 2 == 0;
    return false;
  });
  const CgParticles p = particles(s, species);
  const TopView view = render_top_view(p, species, kLo, kHi, {0.001, 0.0});
  const CongregationIndex cov = congregation_index(p, species, 0, kLength, 0.1, &view);
  CHECK(cov.coverage_left == 1.0);
  CHECK(cov.coverage_right == 1.0);
  CHECK(cov.coverage_centre == 0.5);
  CHECK(cov.coverage_ratio == 2.0);
}

TEST_CASE("A clump species without a density is warned about: its volume would count the spheres' overlaps", "[cg][particles]") {
  dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
  // Two overlapping 2 mm spheres 2 mm apart: one wheat clump; a loose chaff sphere.
  test::add_clump(s, 0, 1380, {{{0.100, 0.1, 0.02}, 0.002}, {{0.102, 0.1, 0.02}, 0.002}}, {0.101, 0.1, 0.02});
  test::add_sphere(s, 1, 0.002, 100, {0.3, 0.1, 0.02});
  SpeciesTable species = species_from_snapshot(s, {"chaff"});
  const std::vector<std::string> w = clump_volume_warnings(s, species, "cg.yaml");
  REQUIRE(w.size() == 1);  // the loose chaff sphere's volume is exact either way
  CHECK(w[0].find("cg.yaml") != std::string::npos);
  CHECK(w[0].find("'wheat'") != std::string::npos);
  CHECK(w[0].find("species.wheat.density") != std::string::npos);
  // With the density the clump's volume is its mass / density, whatever the overlaps.
  species.density["wheat"] = 1380;
  CHECK(clump_volume_warnings(s, species, "cg.yaml").empty());
  const CgParticles p = particles(s, species);
  CHECK_THAT(p.volume[0] + p.volume[1], WithinRel((s.mass[0] + s.mass[1]) / 1380, 1e-12));
}
