// The shape library: every shipped shape loads, is one rigid piece, and its bounding box matches the
// measured size within 3 %; bad shape files are clear errors.
#include <catch2/catch.hpp>

#include "dem/input_error.hpp"
#include "dem/shape.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale;
using namespace grainscale::dem;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;

TEST_CASE("Shipped shapes match their measured sizes within 3 %", "[dem][shape]") {
  const std::string name = GENERATE("wheat", "barley", "lentil", "chaff", "short_straw");
  const Shape s = load_shape(std::string(GRAINSCALE_SOURCE_DIR "/studies/shapes/") + name + ".yaml");
  INFO(name);
  REQUIRE(!s.measured_size.empty());
  const std::vector<double> dims = s.sorted_dimensions();
  for (std::size_t k = 0; k < s.measured_size.size(); ++k) {
    CHECK_THAT(dims[k], WithinRel(s.measured_size[k], 0.03));
  }
  const MassProperties mp = union_mass_properties(s.spheres);
  const Vec3 b = s.bounding_size();
  CHECK(mp.volume > 0);
  CHECK(mp.volume < b.x * b.y * b.z);  // inside its bounding box
}

TEST_CASE("The wheat clump's volume is close to the spheroid it approximates", "[dem][shape]") {
  // A prolate spheroid 6.7 x 3.3 mm has volume 4/3 pi a b^2 = 38.20 mm^3; the inscribed multi-sphere
  // clump is a little smaller (its outline scallops inwards between spheres).
  const Shape s = load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/wheat.yaml");
  const double spheroid = 4.0 / 3.0 * M_PI * 3.35e-3 * 1.65e-3 * 1.65e-3;
  const double v = union_mass_properties(s.spheres).volume;
  CHECK(v < spheroid);
  CHECK(v > 0.85 * spheroid);
}

TEST_CASE("Bad shape files are rejected with the key and the reason", "[dem][shape]") {
  const grainscale::testing::TempDir tmp;  // a fresh folder: a parallel ctest cannot race on the file
  auto write_tmp = [&](const std::string& text) {
    const std::string p = tmp / "shape.yaml";
    grainscale::testing::write_text(p, text);
    return p;
  };
  CHECK_THROWS_WITH(load_shape(write_tmp("name: x\nspheres:\n  - {center: [0, 0, 0], radius: 1}\n"
                                         "  - {center: [5, 0, 0], radius: 1}\n")),
                    Contains("one rigid piece"));
  CHECK_THROWS_WITH(load_shape(write_tmp("name: x\nspheres:\n  - {center: [0, 0, 0], radius: -1}\n")),
                    Contains("spheres[0].radius"));
  CHECK_THROWS_WITH(load_shape(write_tmp("name: x\nlength_unit: inch\nspheres:\n  - {center: [0, 0, 0], radius: 1}\n")),
                    Contains("length_unit"));
  CHECK_THROWS_WITH(load_shape(write_tmp("name: x\nmeasured_size: [1, 2, 3, 4]\nspheres:\n  - {center: [0, 0, 0], radius: 1}\n")),
                    Contains("measured_size"));
  CHECK_THROWS_AS(load_shape(write_tmp("name: x\nspheres: []\n")), InputError);
}
