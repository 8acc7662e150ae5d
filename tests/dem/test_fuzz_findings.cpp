// Inputs that fuzzing (tests/fuzz/README.md) found to escape as something other than InputError:
// each must now be an InputError naming the file and line.
#include <catch2/catch.hpp>
#include <algorithm>
#include <fstream>
#include <string>

#include "checkpoint_fixture.hpp"
#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "dem/scenario.hpp"
#include "dem/shape.hpp"

using namespace grainscale;
using namespace grainscale::dem;
using Catch::Matchers::Contains;

TEST_CASE("YAML keys that are not plain words are input errors naming file and line", "[dem][input]") {
  const testing::CheckpointTempDir dir;
  // From fuzz_materials: a flow mapping used as a key made yaml-cpp's string conversion throw.
  std::ofstream(dir / "materials.yaml") << "materials:\n  !: {dens,chaff,,,,stio: -0.5}: {rest08}\n";
  CHECK_THROWS_AS(MaterialTable::load(dir / "materials.yaml"), InputError);
  CHECK_THROWS_WITH(MaterialTable::load(dir / "materials.yaml"),
                    Contains("materials.yaml:2") && Contains("not a plain word"));
  const std::string scenario = testing::checkpoint_scenario(0.01);
  const auto lines = std::count(scenario.begin(), scenario.end(), '\n');
  std::ofstream(dir / "scenario.yaml") << scenario << "[1, 2]: 3\n";
  CHECK_THROWS_WITH(load_scenario(dir / "scenario.yaml"),
                    Contains("scenario.yaml:" + std::to_string(lines + 1)) && Contains("not a plain word"));
  std::ofstream(dir / "shape.yaml") << "name: s\nspheres:\n  - {center: [0, 0, 0], radius: 1, {a: 1}: 2}\n";
  CHECK_THROWS_WITH(load_shape(dir / "shape.yaml"), Contains("shape.yaml:3") && Contains("not a plain word"));
}
