// Particles placed inside a wall are an input error naming the batch, the wall and the overlap
// (dem/wall_clearance.hpp), not a blow-up at the first step.
#include <catch2/catch.hpp>
#include <fstream>
#include <string>

#include "checkpoint_fixture.hpp"
#include "dem/input_error.hpp"
#include "dem/scenario.hpp"

using namespace grainscale;
using namespace grainscale::dem;
using Catch::Matchers::Contains;

namespace {

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  REQUIRE(s.find(from) != std::string::npos);
  return s.replace(s.find(from), from.size(), to);
}

BuiltScenario built_from(const testing::CheckpointTempDir& dir, const std::string& text) {
  std::ofstream(dir / "materials.yaml") << testing::kCheckpointMaterials;
  std::ofstream(dir / "scenario.yaml") << text;
  return build(load_scenario(dir / "scenario.yaml"));
}

}  // namespace

TEST_CASE("Particles placed overlapping a wall are an input error naming batch, wall and overlap",
          "[dem][input][insertion]") {
  const testing::CheckpointTempDir dir;
  const std::string good = testing::checkpoint_scenario(0.01);
  SECTION("the shipped fixture is clear") { CHECK_NOTHROW(built_from(dir, good)); }
  SECTION("a region reaching outside the container") {
    const std::string text = replaced(good, "region: {min: [0.001, 0.001, 0.016], max: [0.039, 0.029, 0.045]}",
                                      "region: {min: [-0.01, 0.001, 0.016], max: [0.039, 0.029, 0.045]}");
    CHECK_THROWS_AS(built_from(dir, text), InputError);
    CHECK_THROWS_WITH(built_from(dir, text), Contains("scenario.yaml: particles[1].region") &&
                                                 Contains("overlaps wall 'box'") && Contains("% of its radius"));
  }
  SECTION("a container narrower than the particles") {
    // A 2 mm wide slot for 3 mm spheres (the wide region straddles it).
    std::string text = replaced(good, "max: [0.04, 0.03, 0.06], open: [+z]", "max: [0.04, 0.002, 0.06], open: [+z]");
    CHECK_THROWS_WITH(built_from(dir, text), Contains("].region: a particle placed") && Contains("wall 'box'"));
  }
  SECTION("a pour region that the moving box sweeps through, found when the pour places particles") {
    // The box surges 2 mm either way: a region as wide as the box at rest meets its sides. (A larger
    // rate places more particles per insertion, so that one soon lands where a side has come.)
    const std::string text = replaced(replaced(good, "region: {min: [0.003, 0.001, 0.045], max: [0.037, 0.029, 0.059]}",
                                               "region: {min: [0.0, 0.001, 0.045], max: [0.04, 0.029, 0.059]}"),
                                      "rate: 0.012", "rate: 0.1");
    BuiltScenario run = built_from(dir, text);
    run.sim->setup();
    CHECK_THROWS_WITH(
        [&] {
          while (run.sim->time() < 0.04) run.advance();
        }(),
        Contains("particles[2].region") && Contains("wall 'box'"));
  }
}
