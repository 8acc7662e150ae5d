// The calibration machinery around the virtual AOR test: the bracketed search on known monotone
// functions (with and without noise), the generated rig scenario, the study file, the materials
// file written back, the sensitivity figure. A real (small, 2x) AOR run is the hidden [.validate]
// test at the end: minutes, not seconds.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "dem/scenario.hpp"
#include "studies/aor_materials_file.hpp"
#include "studies/aor_profile_plot.hpp"
#include "studies/aor_rig.hpp"
#include "studies/aor_run.hpp"
#include "studies/aor_search.hpp"
#include "studies/aor_sensitivity_plot.hpp"
#include "studies/aor_study.hpp"

using namespace grainscale;
using namespace grainscale::studies;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

const std::filesystem::path kSource = std::filesystem::path(__FILE__).parent_path().parent_path().parent_path();

/// A file in a fresh temporary folder, removed with the object.
struct TempFile {
  std::filesystem::path dir, path;
  TempFile(const std::string& name, const std::string& text) {
    dir = std::filesystem::temp_directory_path() /
          ("grainscale_aor_" + std::to_string(std::hash<std::string>{}(name + text)));
    std::filesystem::create_directories(dir);
    path = dir / name;
    std::ofstream(path) << text;
  }
  ~TempFile() { std::filesystem::remove_all(dir); }
};

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("The calibration search finds the target of a monotone angle within the tolerance", "[studies][aor]") {
  SearchSettings s;
  s.target = 26.67;
  s.tolerance = 0.5;
  s.max_runs = 8;
  SECTION("linear, starting low") {
    s.start = 0.1;
    const SearchResult r = bracketed_search([](double t) { return 15 + 30 * t; }, s);
    CHECK(r.converged);
    CHECK(r.points.size() <= 3);
    CHECK_THAT(r.points[r.best].angle, WithinAbs(26.67, 0.5));
  }
  SECTION("saturating (steep then flat), starting high") {
    s.start = 0.9;
    const SearchResult r = bracketed_search([](double t) { return 18 + 14 * std::sqrt(t); }, s);
    CHECK(r.converged);
    CHECK(r.points.size() <= 5);
    CHECK_THAT(r.points[r.best].angle, WithinAbs(26.67, 0.5));
  }
  SECTION("noisy: +-0.4 deg on every run") {
    s.start = 0.5;
    int calls = 0;
    const SearchResult r = bracketed_search(
        [&](double t) { return 20 + 10 * t + 0.4 * std::sin(12.9898 * ++calls); }, s);
    CHECK(r.converged);
    CHECK(static_cast<int>(r.points.size()) <= s.max_runs);
    // The chosen point is within the tolerance of the noise-free target point t = 0.667 +- 0.09.
    CHECK_THAT(r.points[r.best].t, WithinAbs(0.667, 0.09));
  }
  SECTION("a tight tolerance spends the budget and interpolates inside the bracket") {
    s.tolerance = 1e-6;
    s.max_runs = 4;
    s.start = 0.2;
    const SearchResult r = bracketed_search([](double t) { return 15 + 30 * t * t; }, s);
    CHECK_FALSE(r.converged);
    CHECK(r.points.size() == 4);
    CHECK(r.bracketed);
    CHECK_THAT(r.status, Contains("budget"));
    CHECK_THAT(r.interpolated_t, WithinAbs(std::sqrt(11.67 / 30), 0.05));
  }
  SECTION("a target outside the range stops at its end and says so") {
    s.start = 0.5;
    const SearchResult r = bracketed_search([](double t) { return 10 + 5 * t; }, s);
    CHECK_FALSE(r.converged);
    CHECK_FALSE(r.bracketed);
    CHECK(r.points.back().t == 1.0);
    CHECK_THAT(r.status, Contains("outside the searched range"));
  }
  SECTION("a failed run stops the search") {
    const SearchResult r = bracketed_search([](double) { return std::nan(""); }, s);
    CHECK(r.points.size() == 1);
    CHECK_THAT(r.status, Contains("gave no angle"));
  }
}

TEST_CASE("The AOR rig scenario: pipe on the tray, lifted at the set speed from start_time, poured from above",
          "[studies][aor]") {
  AorCase c;
  c.name = "rig_test";
  c.materials_file = (kSource / "studies/materials/report_table1.yaml").string();
  c.scale_factor = 2;
  c.grain.shape = (kSource / "studies/shapes/barley.yaml").string();
  c.rig.lift_speed = 0.02;
  c.grain.mass = 100 * aor_particle_mass(c);
  // 2x barley clump: 8 x 47.79 mm^3 at 1380 kg/m^3.
  CHECK_THAT(aor_particle_mass(c), WithinRel(8 * 47.79e-9 * 1380, 1e-3));
  TempFile f("rig.yaml", aor_scenario_yaml(c, "unused", 1.25));
  const dem::Scenario s = dem::load_scenario(f.path.string());
  REQUIRE(s.walls.size() == 3);
  CHECK(s.walls[0].name == "tray");
  CHECK(s.walls[1].name == "pipe");
  CHECK(s.walls[2].name == "floor");
  REQUIRE(s.particles.size() == 1);
  CHECK(s.particles[0].rate == c.grain.pour_rate);
  CHECK_THAT(s.particles[0].batch.mass, WithinRel(c.grain.mass, 1e-9));
  // The pour region lies inside the pipe's bore, above its nominal length.
  const auto& b = s.particles[0].batch;
  CHECK(b.region_min.z == 0.3);
  CHECK(b.region_max.z == 0.4);
  CHECK(b.region_max.x * std::sqrt(2.0) < 0.05);
  CHECK(s.end_time == aor_schedule(c, 1.25).end_time);
  dem::BuiltScenario built = dem::build(s);
  dem::Wall& pipe = built.sim->walls()[1];
  REQUIRE(pipe.moving());
  pipe.move_to(1.2);
  CHECK(pipe.pose().origin.z == 0);
  pipe.move_to(3.25);
  CHECK_THAT(pipe.pose().origin.z, WithinAbs(0.04, 1e-12));
  CHECK_THAT(pipe.pose().velocity.z, WithinAbs(0.02, 1e-12));
  {
    dem::Vec3 lo, hi;
    built.sim->walls()[0].geometry().bounds(lo, hi);
    CHECK_THAT(hi.x, WithinAbs(0.1, 1e-9));
    CHECK_THAT(hi.z, WithinAbs(0.0225, 1e-12));
  }
}

TEST_CASE("The calibration study file loads, and bad ones are rejected with file, key and range", "[studies][aor]") {
  const std::string file = (kSource / "studies/aor_calibration.yaml").string();
  const CalibrationStudy s = load_calibration_study(file);
  CHECK(s.scale_factor == 2);
  REQUIRE(s.cases.size() >= 2);
  CHECK(s.cases[0].target_deg == 26.67);
  CHECK(s.cases[0].parameters.front().property == "friction");
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto load_text = [&](const std::string& t) {
    TempFile f("study.yaml", replace(replace(t, "materials/report_table1.yaml", (kSource / "studies/materials/report_table1.yaml").string()),
                                     "shapes/barley.yaml", (kSource / "studies/shapes/barley.yaml").string()));
    return load_calibration_study(f.path.string());
  };
  CHECK_NOTHROW(load_text(text));
  CHECK_THROWS_WITH(load_text(replace(text, "target_deg:", "target_degrees:")), Contains("cases[0].target_deg"));
  CHECK_THROWS_WITH(load_text(replace(text, "pair: barley-barley", "pair: barley-wheat")), Contains("wheat"));
  CHECK_THROWS_WITH(load_text(replace(text, "property: friction", "property: restitution")), Contains("friction, rolling_friction"));
  CHECK_THROWS_AS(load_text(replace(text, "tolerance_deg: 0.5", "tolerance_deg: -1")), InputError);
}

TEST_CASE("Calibrate --case keeps the named cases of a calibration study; an unknown name names the study and its cases",
          "[studies][aor]") {
  const std::string file = (kSource / "studies/aor_calibration.yaml").string();
  const CalibrationStudy all = load_calibration_study(file);
  REQUIRE(all.cases.size() >= 4);
  CalibrationStudy s = all;
  select_cases(s, {});
  CHECK(s.cases.size() == all.cases.size());
  select_cases(s, {"wheat", "barley"});  // kept in the study's order
  REQUIRE(s.cases.size() == 2);
  CHECK(s.cases[0].name == "barley");
  CHECK(s.cases[1].name == "wheat");
  s = all;
  CHECK_THROWS_AS(select_cases(s, {"barley", "oats"}), InputError);
  CHECK_THROWS_WITH(select_cases(s, {"oats"}),
                    Contains("oats") && Contains("aor_calibration.yaml") && Contains("barley, wheat, lentils, chaff"));
  CHECK(s.cases.size() == all.cases.size());  // a failed selection leaves the study as it was
}

TEST_CASE("A materials table written back loads as the same table", "[studies][aor]") {
  dem::MaterialTable t = dem::MaterialTable::load((kSource / "studies/materials/report_table1.yaml").string());
  set_pair_property(t, "barley-barley", "friction", 0.4123456789, "test");
  set_pair_property(t, "barley-perspex", "rolling_friction", 0.02, "test");
  TempFile f("m.yaml", materials_yaml(t, "a header\nof two lines"));
  const dem::MaterialTable u = dem::MaterialTable::load(f.path.string());
  REQUIRE(u.size() == t.size());
  for (int a = 0; a < t.size(); ++a) {
    CHECK(u[a].name == t[a].name);
    CHECK(u[a].shear_modulus == t[a].shear_modulus);
    for (int b = 0; b < t.size(); ++b) {
      REQUIRE(u.has_pair(a, b) == t.has_pair(a, b));
      if (!t.has_pair(a, b)) continue;
      CHECK(u.pair(a, b).friction == t.pair(a, b).friction);
      CHECK(u.pair(a, b).rolling_friction == t.pair(a, b).rolling_friction);
      CHECK(u.pair(a, b).restitution == t.pair(a, b).restitution);
    }
  }
  CHECK(pair_property(u, "barley-barley", "friction", "test") == 0.4123456789);
  CHECK_THROWS_WITH(set_pair_property(t, "perspex-perspex", "friction", 0.1, "ctx"), Contains("ctx") && Contains("perspex-perspex"));
  CHECK_THROWS_AS(pair_property(t, "barley-barley", "stickiness", "ctx"), InputError);
}

TEST_CASE("The sensitivity figure draws one panel per parameter", "[studies][aor]") {
  SensitivityFigure f;
  f.title = "test";
  f.parameters = {"barley-barley friction"};
  f.points = {{{0.3}, 24.0, 1.0}, {{0.5}, 27.5, 0.8}, {{0.42}, 26.6, 0.9}};
  f.target = 26.67;
  f.chosen = {0.42};
  const Image one = draw_sensitivity(f);
  CHECK(one.width() > 300);
  f.parameters.push_back("barley-barley rolling_friction");
  for (auto& p : f.points) p.values.push_back(p.values[0] / 5);
  f.chosen.push_back(0.084);
  CHECK(draw_sensitivity(f).width() == 2 * one.width());
  f.parameters.clear();
  CHECK_THROWS_AS(draw_sensitivity(f), std::invalid_argument);

  // The pile's profile figure.
  AngleMeasurement m;
  for (int k = 0; k < 20; ++k) m.profile_r.push_back(0.0025 + 0.005 * k), m.profile_h.push_back(0.07 - 0.5 * 0.005 * k);
  m.mean_deg = 26.57, m.fit_r_inner = 0.02, m.fit_r_outer = 0.08, m.top_height = 0.07, m.base_height = 0.0225;
  CHECK(draw_pile_profile(m, "test").width() == 900);
}

namespace {
// One AOR run of a study's case at its `calibrated:` values, with one seed; its log's lines into
// `log` if given.
AorRunResult run_at_calibrated(const CalibrationStudy& s, const CalibrationCase& k, std::uint64_t seed,
                               std::vector<std::string>* log = nullptr) {
  REQUIRE(k.calibrated.size() == k.parameters.size());
  dem::MaterialTable t = dem::MaterialTable::load(s.materials_file);
  for (std::size_t i = 0; i < k.parameters.size(); ++i) {
    set_pair_property(t, k.parameters[i].pair, k.parameters[i].property, k.calibrated[i], "test");
  }
  TempFile m("materials.yaml", materials_yaml(t, "AOR test run"));
  const AorCase c = aor_case(s, k, seed, m.path.string());
  const std::filesystem::path scenario = m.dir / "scenario.yaml";
  std::ofstream(scenario) << aor_scenario_yaml(c, m.dir.string());
  return run_aor(scenario.string(), c, "", [log](const std::string& line) {
    if (log != nullptr) log->push_back(line);
  });
}
}  // namespace

TEST_CASE("A quick 2x AOR run of barley gives an angle near its calibrated value", "[studies][aor][.validate]") {
  // The study's barley case at its calibrated sliding friction (studies/aor_calibration.yaml,
  // docs/aor_calibration.md): one seed, the band allowing for the seed-to-seed scatter.
  const CalibrationStudy s = load_calibration_study((kSource / "studies/aor_calibration.yaml").string());
  const CalibrationCase& barley = s.cases[0];
  REQUIRE(barley.calibrated.size() == 1);
  const AorRunResult r = run_at_calibrated(s, barley, 3);
  INFO("angle " << r.angle.mean_deg << " +- " << r.angle.spread_deg << " (side " << r.angle.side_mean_deg << ")");
  CHECK(r.at_rest);
  CHECK_THAT(r.angle.mean_deg, WithinAbs(barley.target_deg, 2.0));
}

TEST_CASE("A small 2x AOR run of barley stays in the band its eight-seed calibration set", "[studies][aor]") {
  // The default suite's AOR run: the reduced rig of studies/aor_scale_barley_2x.yaml (60 mm pipe,
  // 120 mm tray, 0.15 kg = about 280 barley clumps at 2x, about a minute on 2 cores), at that
  // study's friction 0.31. The band is the mean +- 2.5 standard deviations of that study run with
  // seeds 1-8 (2026-12-05, docs/aor_calibration.md, "1x against 2x"): surface 12.12, 18.60, 13.92,
  // 20.77, 16.71, 14.94, 17.87, 14.36 deg, 16.16 +- 2.84; side projection 10.68, 19.16, 12.78, 16.75,
  // 18.82, 11.77, 16.28, 12.41 deg, 14.83 +- 3.32. (Seeds 1-3 alone had given 15.52 +- 1.59, a band
  // the next change in the last bit of a force left: a 280-clump pile is a chaotic outcome, and a
  // change of rounding is a new seed.) Frictionless grain falls well below it; a jammed pipe or
  // grains that never leave it give no pile and fail at_rest / the particle count.
  const CalibrationStudy s = load_calibration_study((kSource / "studies/aor_scale_barley_2x.yaml").string());
  REQUIRE(s.scale_factor == 2);
  const CalibrationCase& barley = s.cases.at(0);
  REQUIRE(barley.calibrated.size() == 1);
  std::vector<std::string> log;
  const AorRunResult r = run_at_calibrated(s, barley, 1, &log);
  INFO("angle " << r.angle.mean_deg << " +- " << r.angle.spread_deg << " (side " << r.angle.side_mean_deg << "), "
                << r.bodies_on_tray << " of " << r.bodies << " on the tray");
  // The run's last progress line shows the time step, as a DEM run's do (dem/progress.hpp).
  auto last = std::find_if(log.rbegin(), log.rend(), [](const std::string& l) { return l.rfind("t = ", 0) == 0; });
  REQUIRE(last != log.rend());
  INFO("last progress line: " << *last);
  CHECK(last->find(" | step ") != std::string::npos);
  CHECK(r.at_rest);
  CHECK(r.bodies > 250);
  CHECK(r.bodies_on_tray > 0.95 * r.bodies);
  CHECK_THAT(r.angle.mean_deg, WithinAbs(16.16, 2.5 * 2.84));
  CHECK_THAT(r.angle.side_mean_deg, WithinAbs(14.83, 2.5 * 3.32));
}
