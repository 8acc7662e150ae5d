// Particle scale-up (dem/scaling.hpp, docs/scaling.md): a scaled scenario carries the documented
// parameters, a Hertz contact lasts s times longer at the same impact speed, and narrow containers and
// openings are reported.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "dem/input_error.hpp"
#include "dem/mass_properties.hpp"
#include "dem/scaling.hpp"
#include "dem/scenario.hpp"
#include "dem/time_step.hpp"
#include "impact_fixture.hpp"

using namespace grainscale;
using namespace grainscale::dem;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;

namespace {

/// A scenario file in a fresh temporary folder beside a copy of the report's materials and the
/// barley shape; removed with the object.
struct TempScenario {
  std::filesystem::path dir, path;
  static int& counter() {
    static int n = 0;
    return n;
  }
  TempScenario(const std::string& name, const std::string& text) {
    dir = std::filesystem::temp_directory_path() /
          ("grainscale_scaling_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++) + "_" +
           std::to_string(std::hash<std::string>{}(name + text)));  // unique: ctest -j runs cases in parallel
    std::filesystem::create_directories(dir);
    std::filesystem::copy_file(GRAINSCALE_SOURCE_DIR "/studies/materials/report_table1.yaml", dir / "materials.yaml",
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::copy_file(GRAINSCALE_SOURCE_DIR "/studies/shapes/barley.yaml", dir / "barley.yaml",
                               std::filesystem::copy_options::overwrite_existing);
    path = dir / name;
    std::ofstream(path) << text;
  }
  ~TempScenario() { std::filesystem::remove_all(dir); }
};

/// The angle-of-repose rig at scale factor `s`: pipe 100 mm, tray 200 mm, a few barley clumps.
std::string rig_scenario(double s) {
  return "name: rig\nmaterials: materials.yaml\nscale_factor: " + std::to_string(s) +
         "\ntime: {end: 0.01}\n"
         "walls:\n"
         "  - {name: pipe, type: pipe, radius: 0.05, length: 0.3, material: perspex}\n"
         "  - {name: tray, type: tray, radius: 0.1, rim_height: 0.0225, material: perspex}\n"
         "  - {name: floor, type: plane, point: [0, 0, -0.1], normal: [0, 0, 1], material: perspex}\n"
         "particles:\n"
         "  - {material: barley, shape: barley.yaml, count: 3, region: {min: [-0.035, -0.035, 0.01], "
         "max: [0.035, 0.035, 0.29]}}\n"
         "output: {directory: unused}\n";
}

}  // namespace

TEST_CASE("Scaling rules: shapes grow by s, materials stay, rolling friction follows the chosen rule",
          "[dem][scaling]") {
  const Shape barley = load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/barley.yaml");
  const Shape big = scale_shape(barley, 2);
  REQUIRE(big.spheres.size() == barley.spheres.size());
  for (std::size_t k = 0; k < barley.spheres.size(); ++k) {
    CHECK(big.spheres[k].radius == 2 * barley.spheres[k].radius);
    CHECK(big.spheres[k].center.x == 2 * barley.spheres[k].center.x);
  }
  CHECK_THAT(big.sorted_dimensions()[0], WithinRel(2 * barley.sorted_dimensions()[0], 1e-12));
  CHECK_THAT(big.measured_size[0], WithinRel(2 * barley.measured_size[0], 1e-12));
  // Mass ~ s^3 and moments of inertia ~ s^5 at the same density.
  const MassProperties m1 = union_mass_properties(barley.spheres), m2 = union_mass_properties(big.spheres);
  CHECK_THAT(m2.volume, WithinRel(8 * m1.volume, 1e-3));
  CHECK_THAT(m2.principal_moments.x, WithinRel(32 * m1.principal_moments.x, 1e-3));

  const MaterialTable t = MaterialTable::load(GRAINSCALE_SOURCE_DIR "/studies/materials/report_table1.yaml");
  const int b = t.index("barley"), p = t.index("perspex");
  SECTION("keep: everything unchanged, the rolling lever arm mu_r R grows with R") {
    const MaterialTable k = scale_materials(t, {2, 1, RollingFrictionRule::keep});
    for (int i = 0; i < t.size(); ++i) {
      CHECK(k[i].density == t[i].density);
      CHECK(k[i].shear_modulus == t[i].shear_modulus);
      CHECK(k[i].poisson_ratio == t[i].poisson_ratio);
    }
    CHECK(k.pair(b, b).restitution == 0.5);
    CHECK(k.pair(b, b).friction == 0.35);
    CHECK(k.pair(b, b).rolling_friction == 0.08);
    CHECK(k.pair(b, p).rolling_friction == 0.01);
    CHECK_FALSE(k.has_pair(p, p));
  }
  SECTION("inverse: the lever arm stays in metres, mu_r s is constant") {
    const MaterialTable i2 = scale_materials(t, {2, 1, RollingFrictionRule::inverse});
    CHECK_THAT(i2.pair(b, b).rolling_friction, WithinRel(0.04, 1e-12));
    CHECK(i2.pair(b, b).friction == 0.35);
    CHECK(i2.pair(b, b).restitution == 0.5);
    // Values calibrated at 2x, used at 2x: unchanged; used at 4x: halved.
    CHECK(scale_pair(t.pair(b, b), {2, 2, RollingFrictionRule::inverse}).rolling_friction == 0.08);
    CHECK_THAT(scale_pair(t.pair(b, b), {4, 2, RollingFrictionRule::inverse}).rolling_friction, WithinRel(0.04, 1e-12));
  }
  CHECK_THROWS_AS(scale_materials(t, {0.5, 1, RollingFrictionRule::keep}), InputError);
  CHECK_THROWS_WITH(rolling_friction_rule_from_name("scale"), Contains("keep, inverse"));
}

TEST_CASE("A scaled scenario has the documented parameters: shapes x s, same materials, time step x s",
          "[dem][scaling]") {
  const Shape barley = load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/barley.yaml");
  TempScenario one("one.yaml", rig_scenario(1)), two("two.yaml", rig_scenario(2));
  const Scenario s1 = load_scenario(one.path.string()), s2 = load_scenario(two.path.string());
  CHECK(s2.settings.scale_factor == 2);
  const Shape& shape2 = *s2.particles[0].batch.shape;
  const Shape expected = scale_shape(barley, 2);
  REQUIRE(shape2.spheres.size() == expected.spheres.size());
  for (std::size_t k = 0; k < expected.spheres.size(); ++k) {
    CHECK_THAT(shape2.spheres[k].radius, WithinRel(expected.spheres[k].radius, 1e-12));
    CHECK_THAT(shape2.spheres[k].center.x, WithinRel(expected.spheres[k].center.x, 1e-12));
  }
  BuiltScenario b1 = build(s1), b2 = build(s2);
  b1.sim->setup();
  b2.sim->setup();
  // Materials as in the file (the default rule keeps them all), time step from the scaled sizes.
  const MaterialTable& m = b2.sim->materials();
  const int g = m.index("barley");
  CHECK(m[g].shear_modulus == 2.6e6);
  CHECK(m.pair(g, g).friction == 0.35);
  CHECK(m.pair(g, g).rolling_friction == 0.08);
  CHECK_THAT(b2.sim->dt(), WithinRel(2 * b1.sim->dt(), 1e-12));
  CHECK_THAT(b2.sim->rayleigh_time(), WithinRel(rayleigh_time(2 * 0.7753e-3, m[g]), 1e-3));
}

TEST_CASE("A Hertz contact at s = 2 lasts twice as long as at s = 1 at the same impact speed",
          "[dem][scaling]") {
  // Johnson (1985) eq. 11.47: t_c ~ (m*^2 / (R* E*^2 v))^(1/5); m ~ s^3, R ~ s, E fixed -> t_c ~ s.
  using namespace testing;
  const Solid grain{2 * 2.6e6 * 1.3, 0.3, 1380};  // the report's barley
  for (const double e : {0.5, 0.9}) {
    const MaterialTable mt = impact_materials(grain, grain, e, 0.35);
    const double r = 3.35e-3;
    const double t1 = sphere_on_wall(mt, r, {0, 0, -1}, {}).duration;
    const double t2 = sphere_on_wall(mt, 2 * r, {0, 0, -1}, {}).duration;
    INFO("restitution " << e << ": contact times " << t1 << " s and " << t2 << " s");
    CHECK_THAT(t2, WithinRel(2 * t1, 0.02));
    // And the absolute value is Hertz's for the nearly elastic impact.
    if (e == 0.9) {
      const double m = 1380 * 4.0 / 3 * M_PI * r * r * r, estar = grain.youngs / (1 - 0.09);
      CHECK_THAT(t1, WithinRel(hertz_contact_time(r, m, estar, 1.0), 0.05));
    }
  }
  // Two equal spheres colliding head-on.
  const MaterialTable mt = impact_materials(grain, grain, 0.5, 0.35);
  auto pair_time = [&](double r) {
    Simulation sim(mt, impact_settings(0.01));
    sim.add_sphere(0, r, {-r, 0, 0}, {0.5, 0, 0});
    sim.add_sphere(1, r, {r, 0, 0}, {-0.5, 0, 0});
    return run_impact(sim).duration;
  };
  CHECK_THAT(pair_time(6.7e-3), WithinRel(2 * pair_time(3.35e-3), 0.02));
}

TEST_CASE("Containers and openings only a few scaled particles wide are reported", "[dem][scaling]") {
  TempScenario two("two.yaml", rig_scenario(2)), three("three.yaml", rig_scenario(3));
  const Scenario s2 = load_scenario(two.path.string()), s3 = load_scenario(three.path.string());
  const std::vector<Passage> passages = scenario_passages(s2);
  REQUIRE(passages.size() == 2);  // the floor plane bounds nothing
  CHECK(passages[0].opening);
  CHECK(passages[0].width == 0.1);
  CHECK_FALSE(passages[1].opening);
  CHECK(passages[1].width == 0.2);
  // 2x barley is 15.8 mm long: the pipe is 6.3 lengths wide, the tray 12.7.
  CHECK_THAT(largest_particle_size(s2), WithinRel(15.8e-3, 1e-3));
  CHECK(narrow_passage_warnings(s2).empty());
  // 3x: 23.7 mm; pipe 4.2 (< 6) and tray 8.4 (< 10) lengths.
  const std::vector<std::string> w3 = narrow_passage_warnings(s3);
  REQUIRE(w3.size() == 2);
  CHECK_THAT(w3[0], Contains("wall 'pipe'") && Contains("pipe bore") && Contains("4.22"));
  CHECK_THAT(w3[1], Contains("wall 'tray'") && Contains("8.44"));
  // Limits are parameters.
  CHECK(narrow_passage_warnings(s2, {7, 10}).size() == 1);
  // A box split into compartments is judged by a compartment's length when that is the narrowest.
  std::vector<Passage> box{{"box", "box compartment", 0.1, false}};
  CHECK(narrow_passage_warnings(box, 0.0134, 2).size() == 1);
  CHECK(narrow_passage_warnings(box, 0.0067, 1).empty());
}
