// The closure-vs-DEM comparison (studies/closure_dem_comparison.cpp) on synthetic coarse-grained
// fields whose answers are known in closed form: a planar bed surface at slope s in the box frame and a
// uniform surface speed U, in the default study's box on its platform motion (studies/platform_quick/
// scenario.yaml). The DEM measures must be tilt − atan(s) and U; the closure, started from the same
// bed with friction far above the tilt, must stay exactly at rest (same angle, zero speed), so the
// errors are 0° and U.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>

#include "dem/input_error.hpp"
#include "studies/closure_dem_comparison.hpp"
#include "tests/studies/synthetic_cg_fields.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale;
using grainscale::testing::TempDir;
using grainscale::testing::write_text;

namespace {

const std::string kScenario = std::string(GRAINSCALE_SOURCE_DIR) + "/studies/platform_quick/scenario.yaml";

studies::HoldSettings stiff_material() {
  studies::HoldSettings m;
  m.name = "stiff";
  m.friction.internal_deg = 40, m.friction.basal_deg = 35;  // far above the 14° this test tilts to
  m.friction.grain_diameter = 6.7e-3, m.friction.layer_depth = 0.02;
  return m;
}

}  // namespace

TEST_CASE("Closure vs DEM: a planar DEM surface and a closure bed below its yield give the closed forms",
          "[study][hold][closure]") {
  TempDir dir("closure_dem");
  const double s = 0.05, U = 0.02;
  // The platform starts at 0.4 s (24°, 0.25 Hz): 0.2 and 0.3 s at rest, then tilting.
  grainscale::testing::write_planar_bed_fields(dir / "fields.h5", {0.2, 0.3, 0.9, 1.2, 1.5}, 0.03, s, U);
  const studies::ClosureDemComparison c =
      studies::compare_closure_with_dem(dir / "fields.h5", kScenario, "box", stiff_material(), dir / "out");
  REQUIRE(c.times.size() == 4);  // from the last frame at rest
  CHECK(c.times.front() == 0.3);
  CHECK(c.tilt_deg.front() == Approx(0).margin(1e-9));
  CHECK(c.tilt_deg.back() > 10);
  CHECK(c.fill_height == Approx(0.03).epsilon(1e-12));
  for (std::size_t j = 0; j < c.times.size(); ++j) {
    INFO("t = " << c.times[j]);
    CHECK(c.dem_angle_deg[j] == Approx(c.tilt_deg[j] - std::atan(s) * 180 / M_PI).margin(1e-9));
    CHECK(c.closure_angle_deg[j] == Approx(c.dem_angle_deg[j]).margin(1e-9));
    CHECK(c.dem_speed[j] == Approx(U).epsilon(1e-12));
    CHECK(c.closure_speed[j] == 0);
  }
  // The side walls: the box's 30 mm and barley-perspex sliding friction (studies/materials/report_table1.yaml);
  // the closure with them and the 2-D one without are both at rest here.
  CHECK(c.side_wall_width == Approx(0.03).epsilon(1e-12));
  CHECK(c.side_wall_friction == 0.25);
  CHECK(c.open_angle_deg == c.closure_angle_deg);
  CHECK(c.open_speed == c.closure_speed);
  CHECK(c.angle_rms_error_deg == Approx(0).margin(1e-9));
  CHECK(c.speed_rms_error == Approx(U).epsilon(1e-12));
  CHECK(c.speed_max_error == Approx(U).epsilon(1e-12));
  CHECK_FALSE(c.agrees);  // U = 2 cm/s against a still closure: more than half the DEM's speed
  // The null model (the first bed held rigid) is the closure at rest here: the same errors.
  CHECK(c.still_angle_rms_error_deg == Approx(0).margin(1e-9));
  CHECK(c.still_speed_rms_error == Approx(U).epsilon(1e-12));
  CHECK_FALSE(c.still_agrees);
  CHECK(std::filesystem::exists(dir / "out/comparison.csv"));
  CHECK(std::filesystem::exists(dir / "out/surface_angle.png"));
  // The box is 30 mm (4.5 grain diameters) wide: the report says side-wall friction is missing.
  bool narrow = false;
  for (const auto& n : c.notes) narrow = narrow || n.find("side walls") != std::string::npos;
  CHECK(narrow);
}

TEST_CASE("Closure vs DEM: bad input names the file", "[study][hold][closure][input]") {
  TempDir dir("closure_dem_bad");
  write_text(dir / "not.h5", "not hdf5");
  CHECK_THROWS_WITH(studies::compare_closure_with_dem(dir / "not.h5", kScenario, "box", stiff_material(), dir / "out"),
                    Catch::Contains("not.h5"));
  grainscale::testing::write_planar_bed_fields(dir / "fields.h5", {0.2, 0.3}, 0.03, 0, 0);  // nothing after the motion starts
  CHECK_THROWS_WITH(studies::compare_closure_with_dem(dir / "fields.h5", kScenario, "box", stiff_material(), dir / "out"),
                    Catch::Contains("fewer than 2 frames"));
  grainscale::testing::write_planar_bed_fields(dir / "fields.h5", {0.3, 0.9}, 0.03, 0, 0);
  CHECK_THROWS_WITH(studies::compare_closure_with_dem(dir / "fields.h5", kScenario, "lid", stiff_material(), dir / "out"),
                    Catch::Contains("no moving wall named 'lid'"));
}

// A twin experiment for the friction fit (closure_friction_fit.hpp): "DEM" fields made by the closure
// itself with a known friction (its bed heights per frame, its surface speed in every grain cell), fed
// back with a wrong a-priori friction. The fit must find the known values from the early frames, and
// the fitted closure must then agree on the later frames it was not fitted to, where the a-priori
// one does not.
namespace {

/// The twin's "DEM" fields: the closure of `truth` on a flat 30 mm bed in the platform box, its bed
/// heights and surface speeds per frame written as a cg field file (frames 0.2 to 6.4 s: the
/// platform's swing both ways). Returns the largest |surface speed|.
double write_twin_fields(const TempDir& dir, const studies::HoldSettings& truth) {
  std::vector<double> times;
  for (int j = 2; j <= 64; ++j) times.push_back(0.1 * j);
  // The truth's closure on a flat 30 mm bed (frames at rest: the bed as it was poured).
  grainscale::testing::write_planar_bed_fields(dir / "flat.h5", times, 0.03, 0, 0);
  const studies::ClosureDemComparison made =
      studies::compare_closure_with_dem(dir / "flat.h5", kScenario, "box", truth, dir / "made");
  const std::size_t skipped = times.size() - made.times.size();  // frames before the last at rest
  std::vector<std::vector<double>> h(times.size(), std::vector<double>(30, 0.03));
  std::vector<double> u(times.size(), 0.0);
  double peak = 0;
  for (std::size_t j = 0; j < made.times.size(); ++j) {
    h[skipped + j] = made.closure_depth[j];
    u[skipped + j] = made.closure_speed[j];
    peak = std::max(peak, std::fabs(u[skipped + j]));
  }
  grainscale::testing::write_bed_fields(dir / "twin.h5", times, h, u, 40);
  return peak;
}

}  // namespace

TEST_CASE("Closure friction fit: a twin experiment recovers the friction that made the data",
          "[study][hold][closure][fit]") {
  TempDir dir("closure_fit_twin");
  studies::HoldSettings truth = stiff_material();
  truth.name = "truth";
  truth.friction.internal_deg = 17, truth.friction.basal_deg = 8;  // yields below the 24° tilt, side walls included
  truth.friction.layer_depth = 3 * truth.friction.grain_diameter;
  REQUIRE(write_twin_fields(dir, truth) > 0.05);  // the truth's bed flows: the fit has something to see

  studies::HoldSettings a_priori = truth;
  a_priori.name = "a_priori";
  a_priori.friction.internal_deg = 23, a_priori.friction.basal_deg = 13;
  studies::ClosureFitSettings fs;
  fs.train_until = 3.4;  // the first swing and hold train; the swing back tests
  const studies::ClosureDemComparison c =
      studies::compare_closure_with_dem(dir / "twin.h5", kScenario, "box", a_priori, dir / "out", fs);
  REQUIRE(c.fit);
  const studies::ClosureFit& f = *c.fit;
  REQUIRE(f.names.size() == 3);
  INFO("fitted phi " << f.fitted[0] << ", delta " << f.fitted[1] << ", l/d " << f.fitted[2] << "; J train "
                     << f.fitted_train.objective << ", test " << f.fitted_test.objective << ", a priori test "
                     << f.a_priori_test.objective);
  CHECK(f.a_priori_test.objective > 1);  // the wrong friction fails the bar on the test frames
  CHECK_FALSE(c.still_agrees);  // and so does a bed that never moves: the bar can tell flowing from still
  CHECK_FALSE(f.a_priori_test.agrees);
  CHECK(f.fitted_train.objective < 1e-3);
  CHECK(f.fitted[0] == Approx(17).margin(0.3));
  CHECK(f.fitted[1] == Approx(8).margin(0.3));
  CHECK(f.fitted[2] == Approx(3).epsilon(0.05));
  CHECK(f.fitted_test.agrees);
  CHECK(f.fitted_test.objective < 1e-2);
  const double truth_values[3] = {17, 8, 3};
  for (std::size_t j = 0; j < 3; ++j) {  // the sensitivity ranges hold the truth and are not points
    INFO(f.names[j] << ": " << f.lower[j] << " to " << f.upper[j]);
    CHECK(f.lower[j] < truth_values[j]);
    CHECK(f.upper[j] > truth_values[j]);
  }
  CHECK(f.angle_deg.size() == c.times.size());
}

// The same twin experiment with start/stop hysteresis (bed_friction.hpp, (F3)): the truth starts at
// φ + 2.5° and stops at φ; fitted from no hysteresis and a wrong φ, the fit must find both.
TEST_CASE("Closure friction fit: a twin experiment recovers the start/stop hysteresis that made the data",
          "[study][hold][closure][fit][hysteresis]") {
  TempDir dir("closure_fit_twin_hysteresis");
  studies::HoldSettings truth = stiff_material();
  truth.name = "truth";
  truth.friction.internal_deg = 17, truth.friction.basal_deg = 8, truth.friction.start_excess_deg = 2.5;
  truth.friction.layer_depth = 3 * truth.friction.grain_diameter;
  REQUIRE(write_twin_fields(dir, truth) > 0.05);
  studies::HoldSettings a_priori = truth;
  a_priori.name = "a_priori";
  a_priori.friction.internal_deg = 23, a_priori.friction.start_excess_deg = 0;
  studies::ClosureFitSettings fs;
  fs.train_until = 3.4;
  fs.parameters = {"internal_friction_deg", "start_excess_deg"};
  const studies::ClosureDemComparison c =
      studies::compare_closure_with_dem(dir / "twin.h5", kScenario, "box", a_priori, dir / "out", fs);
  REQUIRE(c.fit);
  const studies::ClosureFit& f = *c.fit;
  INFO("fitted phi " << f.fitted[0] << " (" << f.lower[0] << " to " << f.upper[0] << "), excess " << f.fitted[1] << " ("
                     << f.lower[1] << " to " << f.upper[1] << "); J train " << f.fitted_train.objective << ", test "
                     << f.fitted_test.objective << ", a priori test " << f.a_priori_test.objective);
  CHECK_FALSE(f.a_priori_test.agrees);
  CHECK(f.fitted[0] == Approx(17).margin(0.3));
  CHECK(f.fitted[1] == Approx(2.5).margin(0.3));
  CHECK(f.fitted_test.agrees);
  CHECK(f.lower[1] < 2.5);
  CHECK(f.upper[1] > 2.5);
  CHECK(f.lower[1] > 0);  // the data demand hysteresis: none is outside the range
}

TEST_CASE("Closure friction fit: a split without 3 frames on each side, or an unknown parameter, is an input error",
          "[study][hold][closure][fit][input]") {
  TempDir dir("closure_fit_bad");
  std::vector<double> times;
  for (int j = 2; j <= 20; ++j) times.push_back(0.1 * j);
  grainscale::testing::write_planar_bed_fields(dir / "fields.h5", times, 0.03, 0, 0);
  studies::ClosureFitSettings fs;
  fs.train_until = 1.9;  // two test frames left
  CHECK_THROWS_WITH(studies::compare_closure_with_dem(dir / "fields.h5", kScenario, "box", stiff_material(), dir / "out", fs),
                    Catch::Contains("fields.h5") && Catch::Contains("train_until") && Catch::Contains("at least 3"));
  fs.train_until = 1.0;
  fs.parameters = {"angle_of_repose"};
  CHECK_THROWS_WITH(studies::compare_closure_with_dem(dir / "fields.h5", kScenario, "box", stiff_material(), dir / "out", fs),
                    Catch::Contains("'angle_of_repose'") && Catch::Contains("basal_friction_deg"));
}
