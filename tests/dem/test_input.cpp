// Bad input gets a clear error naming the file, the key and the allowed range; the shipped inputs load.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "dem/scenario.hpp"
#include "dem/time_step.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale;
using namespace grainscale::dem;
using Catch::Matchers::Contains;

namespace {

/// A YAML file in a fresh temporary folder, removed with the object. The folder is mkdtemp's, not
/// named from the text: two processes (ctest -j, or two checkouts) writing the same case would
/// otherwise share it and remove it under each other.
struct TempYaml {
  grainscale::testing::TempDir tmp;
  std::filesystem::path path;
  TempYaml(const std::string& name, const std::string& text) : path(tmp.path / name) {
    grainscale::testing::write_text(path.string(), text);
  }
};

const std::string kGoodMaterials = R"(materials:
  grain: {density: 1380, shear_modulus: 2.6e6, poisson_ratio: 0.3}
  wall:  {density: 1190, shear_modulus: 7.97e8, poisson_ratio: 0.38}
pairs:
  grain-grain: {restitution: 0.5, friction: 0.35, rolling_friction: 0.08}
  grain-wall:  {restitution: 0.5, friction: 0.25, rolling_friction: 0.01}
)";

std::string replace(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

}  // namespace

TEST_CASE("The report's Table 1 ships as a materials file and loads", "[dem][input]") {
  const MaterialTable t = MaterialTable::load(GRAINSCALE_SOURCE_DIR "/studies/materials/report_table1.yaml");
  REQUIRE(t.size() == 3);
  const int barley = t.index("barley"), chaff = t.index("chaff"), perspex = t.index("perspex");
  CHECK(t[barley].density == 1380);
  CHECK(t[chaff].shear_modulus == 1.0e6);
  CHECK(t[perspex].poisson_ratio == 0.38);
  CHECK(t.pair(chaff, barley).restitution == 0.2);
  CHECK(t.pair(barley, chaff).friction == 0.3);  // symmetric
  CHECK(t.pair(barley, barley).rolling_friction == 0.08);
  CHECK(t.pair(chaff, perspex).restitution == 0.1);
  CHECK_THROWS_WITH(t.pair(perspex, perspex), Contains("perspex-perspex"));
}

TEST_CASE("Bad materials files are rejected with file, line, key and range", "[dem][input]") {
  struct Case {
    std::string from, to, expect;
  };
  const Case c = GENERATE(Case{"density: 1380", "density: -5", "materials.grain.density"},
                          Case{"poisson_ratio: 0.3", "poisson_ratio: 0.5", "allowed (-1, 0.5)"},
                          Case{"restitution: 0.5, friction: 0.35", "restitution: 1.5, friction: 0.35", "(0, 1]"},
                          Case{"restitution: 0.5, friction: 0.35", "restitution: 0, friction: 0.35", "restitution"},
                          Case{"friction: 0.35", "friction: -0.1", "pairs.grain-grain.friction"},
                          Case{"friction: 0.35", "friction: lots", "must be a number"},
                          Case{"grain-wall:", "grain-sand:", "unknown material 'sand'"},
                          Case{"rolling_friction: 0.08", "rolling_friction: 0.08, resitution: 1", "unknown key"},
                          Case{"shear_modulus: 2.6e6", "shear_modulus: 0", "shear_modulus"});
  const TempYaml f("materials.yaml", replace(kGoodMaterials, c.from, c.to));
  INFO(c.to);
  CHECK_THROWS_AS(MaterialTable::load(f.path.string()), InputError);
  CHECK_THROWS_WITH(MaterialTable::load(f.path.string()), Contains(c.expect) && Contains("materials.yaml:"));
}

TEST_CASE("Missing and malformed files are clear errors", "[dem][input]") {
  CHECK_THROWS_WITH(MaterialTable::load("/nonexistent/m.yaml"), Contains("/nonexistent/m.yaml") && Contains("cannot open"));
  const TempYaml f("broken.yaml", "materials: {grain: [1, 2\n");
  CHECK_THROWS_WITH(MaterialTable::load(f.path.string()), Contains("broken.yaml") && Contains("syntax"));
}

namespace {

const std::string kGoodScenario = R"(name: tiny
seed: 3
materials: materials.yaml
time: {end: 0.01}
walls:
  - {name: box, type: box, min: [0, 0, 0], max: [0.05, 0.05, 0.1], open: [+z], material: wall}
particles:
  - {material: grain, diameter: 0.004, count: 50, region: {min: [0, 0, 0], max: [0.05, 0.05, 0.1]}}
output: {directory: out}
)";

struct ScenarioFiles {
  TempYaml materials, scenario;
  ScenarioFiles(const std::string& text)
      : materials("materials.yaml", kGoodMaterials), scenario("scenario.yaml", text) {
    std::filesystem::copy_file(materials.path, scenario.tmp.path / "materials.yaml",
                               std::filesystem::copy_options::overwrite_existing);
  }
};

}  // namespace

TEST_CASE("A scenario's mesh wall with a motion moves as the profile says", "[dem][input][motion]") {
  const ScenarioFiles f(replace(kGoodScenario, "type: box, min: [0, 0, 0], max: [0.05, 0.05, 0.1], open: [+z], material: wall}",
                                "type: box_mesh, min: [0, 0, 0], max: [0.05, 0.05, 0.1], open: [+z], material: wall, "
                                "pivot: [0, 0, -0.2], motion: {type: steady, velocity: [0, 0, 0.5], start_time: 0.004}}"));
  BuiltScenario built = build(load_scenario(f.scenario.path.string()));
  REQUIRE(built.sim->walls().size() == 1);
  CHECK(built.sim->walls()[0].moving());
  while (built.sim->time() < 0.01) built.advance();
  // At rest until 0.004 s, then rising at 0.5 m/s.
  CHECK_THAT(built.sim->walls()[0].pose().origin.z, Catch::Matchers::WithinAbs(0.5 * (built.sim->time() - 0.004), 1e-12));
  CHECK(built.sim->walls()[0].pose().velocity.z == 0.5);
}

TEST_CASE("A scenario builds the walls and inserts the particles it describes", "[dem][input]") {
  const ScenarioFiles f(kGoodScenario);
  const Scenario s = load_scenario(f.scenario.path.string());
  auto sim = std::move(build(s).sim);
  CHECK(sim->particles().size() == 50);
  REQUIRE(sim->walls().size() == 1);
  for (std::size_t i = 0; i < sim->particles().size(); ++i) {
    const Vec3 x = sim->particles().x[i];
    const double r = sim->particles().radius[i];
    CHECK((x.x >= r && x.x <= 0.05 - r && x.y >= r && x.y <= 0.05 - r && x.z >= r && x.z <= 0.1 - r));
    for (std::size_t j = i + 1; j < sim->particles().size(); ++j) {
      CHECK(norm(x - sim->particles().x[j]) >= r + sim->particles().radius[j]);  // no overlaps
    }
  }
  auto again = std::move(build(s).sim);  // same seed, same particles
  CHECK(again->particles().x == sim->particles().x);
  sim->run_steps(10);  // and it runs
}

TEST_CASE("Bad scenarios are rejected with file, line, key and range", "[dem][input]") {
  struct Case {
    std::string from, to, expect;
  };
  const Case c = GENERATE(
      Case{"end: 0.01", "end: -1", "time.end"}, Case{"end: 0.01", "end: 0.01, stp: 1", "unknown key 'time.stp'"},
      Case{"end: 0.01", "end: 0.01, list_frame: box", "time.list_frame"},
      Case{"open: [+z]", "open: [top]", "'top' is not allowed"}, Case{"type: box", "type: sphere", "choose one of"},
      Case{"material: wall}", "material: steel}", "unknown material 'steel'"},
      Case{"count: 50", "count: 50, mass: 1", "exactly one of"},
      Case{"diameter: 0.004", "diameter: 0.2", "narrower than the largest particle"},
      Case{"count: 50", "count: 100000", "random insertion jams"},
      Case{"max: [0.05, 0.05, 0.1], open", "max: [0.05, 0.05], open", "list of 3 numbers"},
      Case{"materials: materials.yaml", "materials: nothere.yaml", "nothere.yaml"},
      Case{"name: box,", "name: a/b,", "wall name 'a/b' is not allowed"},
      Case{"type: box,", "type: box_mesh, compartments: 0,", "walls[0].compartments"},
      Case{"type: box,", "type: stl, file: missing.stl,", "missing.stl: cannot open"},
      Case{"material: wall}", "material: wall, motion: {type: platform, amplitude_deg: 120}}", "amplitude_deg"},
      Case{"material: wall}", "material: wall, motion: {type: platform, amplitude_deg: 20, axis: [0, 0, 0]}}",
           "axis' must not be the zero vector"},
      Case{"material: wall}", "material: wall, motion: {type: sinusoids}}", "needs at least one of roll"},
      Case{"material: wall}", "material: wall, motion: {type: sinusoids, roll: {amplitude_deg: 5, period: -1}}}",
           "roll.period"},
      Case{"material: wall}", "material: wall, motion: {type: steady, velocity: [0, 0, 1], speed: 1}}", "unknown key"},
      Case{"material: wall}", "material: wall, pivot: [0, 0, 0]}", "only meaningful with 'motion'"});
  const ScenarioFiles f(replace(kGoodScenario, c.from, c.to));
  INFO(c.to);
  CHECK_THROWS_AS(build(load_scenario(f.scenario.path.string())), InputError);
  CHECK_THROWS_WITH(build(load_scenario(f.scenario.path.string())), Contains(c.expect));
}

TEST_CASE("A scenario batch with a shape inserts clumps, scaled by the scale factor, randomly oriented",
          "[dem][input][clump]") {
  const std::string shapes = GRAINSCALE_SOURCE_DIR "/studies/shapes/";
  const ScenarioFiles f(replace(replace(kGoodScenario, "name: tiny", "name: tiny\nscale_factor: 2"),
                                "{material: grain, diameter: 0.004, count: 50,",
                                "{material: grain, shape: " + shapes + "wheat.yaml, particle_mass: 4.0e-4, count: 20,"));
  BuiltScenario built = build(load_scenario(f.scenario.path.string()));
  auto& sim = built.sim;
  const std::vector<std::string>& report = built.report;
  REQUIRE(sim->bodies().size() == 20);
  CHECK(sim->particles().size() == 140);
  CHECK_THAT(sim->bodies().mass[0], Catch::Matchers::WithinRel(4.0e-4, 1e-12));  // density set from the mass
  REQUIRE(report.size() == 1);
  CHECK_THAT(report[0], Contains("placed 20 wheat clumps") && Contains("particle_mass"));
  // Scaled by 2: the largest sphere is 2 x 1.65 mm.
  double r_max = 0;
  for (double r : sim->particles().radius) r_max = std::max(r_max, r);
  CHECK_THAT(r_max, Catch::Matchers::WithinRel(3.3e-3, 1e-12));
  // Random orientations: not all the same.
  CHECK(sim->bodies().q[0].w != sim->bodies().q[1].w);
  sim->run_steps(10);

  const ScenarioFiles both(replace(kGoodScenario, "{material: grain, diameter: 0.004,",
                                   "{material: grain, shape: " + shapes + "wheat.yaml, diameter: 0.004,"));
  CHECK_THROWS_WITH(load_scenario(both.scenario.path.string()), Contains("either 'shape' or 'diameter'"));
}

TEST_CASE("A scenario batch with a rate is poured during the run; the time step covers it from the start",
          "[dem][input][insertion]") {
  const ScenarioFiles f(replace(replace(kGoodScenario, "count: 50,", "mass: 0.004, rate: 0.2, start: 0.002,"),
                                "time: {end: 0.01}", "time: {end: 0.05, pour_interval: 0.005}"));
  const Scenario s = load_scenario(f.scenario.path.string());
  BuiltScenario built = build(s);
  CHECK(built.sim->particles().size() == 0);  // nothing placed at t = 0
  REQUIRE(built.pours.size() == 1);
  // The step was chosen for the poured 4 mm grains before any exists.
  const double expected = 0.2 * rayleigh_time(0.002, built.sim->materials()[0]);
  CHECK_THAT(built.sim->settings().time_step, Catch::Matchers::WithinRel(expected, 1e-12));
  // So was the adaptive Verlet skin's bound (0.2 x the largest radius): with none, the list would be
  // rebuilt every step.
  CHECK(built.sim->settings().skin == 0);
  CHECK_THAT(built.sim->settings().skin_max, Catch::Matchers::WithinRel(0.2 * 0.002, 1e-12));
  while (built.sim->time() < s.end_time) built.advance();
  CHECK(!built.pouring());
  CHECK(built.sim->particles().size() > 0);
  CHECK_THAT(built.pour_report()[0], Contains("poured"));
}
