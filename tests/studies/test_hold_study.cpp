// `kind: hold` studies (studies/hold_study*.cpp): a reduced variant (two small rocking boxes and a box
// too gently tilted to flow, shortened by the study file) runs end to end and its report has every
// section; a bed that never flows keeps the end enrichment at exactly 1; the report's measured
// coverage pair is turned into the visible-chaff ratio ln(0.4)/ln(0.9); bad study files name the file
// and the key; `grainscale study` reaches the hold runner through the file's kind; with `validate`, the
// report carries the closure-vs-DEM section (synthetic fields: closed forms in
// test_closure_dem_comparison.cpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "dem/input_error.hpp"
#include "studies/hold_study.hpp"
#include "studies/hold_study_report.hpp"
#include "studies/study_kinds.hpp"
#include "tests/studies/synthetic_cg_fields.hpp"
#include "tests/command_output.hpp"
#include "tests/input_error_check.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale;
using grainscale::testing::slurp;
using grainscale::testing::replace_in_file;
using grainscale::testing::require_input_error;
using grainscale::testing::TempDir;
using grainscale::testing::write_text;
namespace fs = std::filesystem;

namespace {

/// A 0.4 m box with 30 mm of grain rocked about its floor centre (as tests/studies/test_hold.cpp):
/// it flows every half cycle when `amplitude_deg` is 30, never at 2 (below the 15° floor friction).
std::string box_yaml(const std::string& name, double amplitude_deg, const std::string& resolve = "all") {
  return "name: " + name + "\n" +
         "container: {length: 0.4, depth: 0.1, fill_height: 0.03, pivot: [0.2, 0], nx: 32}\n"
         "motion: {type: sinusoids, pitch: {amplitude_deg: " + std::to_string(amplitude_deg) + ", period: 4}}\n"
         "material: {internal_friction_deg: 25, basal_friction_deg: 15, delta_mu: 0.26, grain_diameter: 3.0e-3,\n"
         "           flowing_layer_diameters: 3}\n"
         "chaff:\n"
         "  window: 0.03\n"
         "  nz: 8\n"
         "  initial: 0.05\n"
         "  terms:\n"
         "    advection: {limiter: van_leer}\n"
         "    segregation: {S: 2.0e-4, limiter: van_leer}\n"
         "    shear_diffusion: {C: 0.04, d: 3.0e-3}\n"
         "time: {end: 400, outputs: 10, resolve: " + resolve + "}\n"
         "output: {folder: unused, end_zone: 0.05, top_layer: 0.005, spear_depth: 0.03}\n";
}

void write_reduced(const TempDir& dir, const std::string& scenarios_extra = "", const std::string& extra = "") {
  write_text(dir / "rocking.yaml", box_yaml("rocking", 30));
  write_text(dir / "rocking_long.yaml", box_yaml("rocking_long", 30, "12"));
  write_text(dir / "still.yaml", box_yaml("still", 2));
  write_text(dir / "study.yaml", "kind: hold\nname: reduced_hold\n"
                                 "scenarios:\n"
                                 "  - {file: still.yaml, end: 20}\n"
                                 "  - {file: rocking.yaml, end: 40, compare_with_report: true}\n"
                                 "  - {file: rocking_long.yaml, end: 80}\n" +
                                     scenarios_extra + "output: {directory: out}\n" + extra);
}

}  // namespace

TEST_CASE("The reduced hold study runs every scenario and reports every section", "[study][hold]") {
  TempDir dir("hold_study");
  write_reduced(dir);
  const studies::HoldStudySettings s = studies::load_hold_study_settings(dir / "study.yaml");
  REQUIRE(s.scenarios.size() == 3);
  CHECK(s.scenarios[1].shortened);
  CHECK(s.scenarios[1].settings.t_end == 40);
  CHECK(s.scenarios[1].settings.resolved_chunks == 10);  // "all" stays all
  CHECK(s.scenarios[2].settings.resolved_chunks == 12);  // 12 of 20: then the averaged model
  std::string report_path;
  const studies::HoldStudyResults r = studies::run_hold_study(s, studies::StudyOptions{}, report_path);
  const std::string out = dir / "out";
  REQUIRE(report_path == fs::path(out + "/report.md").lexically_normal().string());
  const std::string report = slurp(report_path);
  for (const char* section : {"## What was run", "## Warnings", "## Summary: scenarios ranked by predicted congregation",
                              "Verdict:", "## Scenario 1: still", "## Scenario 2: rocking", "## Scenario 3: rocking_long",
                              "Chaff build-up over time", "## Cost: one day of motion", "## Comparison with the measurements",
                              "## Closure vs DEM", "## Limits"}) {
    INFO(section);
    CHECK(report.find(section) != std::string::npos);
  }
  for (const char* png : {"rocking/surface_chaff.png", "rocking/end_fractions.png", "rocking/chaff_map.png",
                          "rocking/spear.png", "rocking/surface.png", "still/spear.png"}) {
    INFO(png);
    CHECK(fs::exists(out + "/" + png));
    CHECK(report.find(std::string("](") + png + ")") != std::string::npos);
  }
  CHECK(fs::exists(out + "/log.txt"));
  CHECK(fs::exists(out + "/inputs/study.yaml"));
  CHECK(fs::exists(out + "/inputs/rocking.yaml"));
  CHECK(fs::exists(out + "/rocking_long/summary.yaml"));

  REQUIRE(r.scenarios.size() == 3);
  const auto& still = r.scenarios[0];
  const auto& rocking = r.scenarios[1];
  const auto& longer = r.scenarios[2];
  CHECK(rocking.times.back() == Approx(40));
  CHECK(longer.averaged);
  CHECK_FALSE(rocking.averaged);
  // A bed that never yields carries nothing: the chaff stays as loaded, so E = 1 and the surface
  // concentration at the ends equals the loading value (exact: no flux at all).
  CHECK(still.closure_steps > 0);
  CHECK(still.enrichment_left == Approx(1).margin(1e-12));
  CHECK(still.enrichment_right == Approx(1).margin(1e-12));
  CHECK(still.surface_right.back() == Approx(0.05).margin(1e-12));
  CHECK(still.dirty.empty());
  // The rocking box moves chaff (and conserves it); the still box ranks below it.
  CHECK(std::fabs(rocking.enrichment() - 1) > 1e-3);
  CHECK(std::fabs(rocking.chaff_relative_change) < 1e-9);
  CHECK(std::fabs(longer.chaff_relative_change) < 1e-9);
  CHECK(report.find("the least in `still`") != std::string::npos);
  // Shortened scenarios are warned about; the uniform share is the zones' share of the window.
  CHECK(report.find("shortened by the study file to 40 s") != std::string::npos);
  CHECK(rocking.uniform_left == Approx(0.05 * 0.005 / (0.4 * 0.03)).epsilon(0.05));
  CHECK(report.find("Verdict for `rocking`") != std::string::npos);
  CHECK(report.find("Verdict for `still`") == std::string::npos);
}

TEST_CASE("A hold study with validate reports the closure against the coarse-grained DEM", "[study][hold][closure]") {
  TempDir dir("hold_study_validate");
  grainscale::testing::write_planar_bed_fields(dir / "fields.h5", {0.3, 0.9, 1.5}, 0.03, 0.05, 0.02);
  write_text(dir / "still.yaml", box_yaml("still", 2));
  write_text(dir / "study.yaml", "kind: hold\nname: validated\nscenarios:\n  - {file: still.yaml, end: 8}\n"
                                 "validate: {cg_fields: fields.h5, dem_scenario: " + std::string(GRAINSCALE_SOURCE_DIR) +
                                     "/studies/platform_quick/scenario.yaml, material_from: still}\n"
                                 "output: {directory: out}\n");
  std::string report_path;
  const studies::HoldStudyResults r =
      studies::run_hold_study(studies::load_hold_study_settings(dir / "study.yaml"), studies::StudyOptions{}, report_path);
  REQUIRE(r.validation);
  CHECK(r.validation->times.size() == 3);
  CHECK(r.validation->speed_rms_error == Approx(0.02).epsilon(1e-9));  // a still closure against 2 cm/s
  const std::string report = slurp(report_path);
  for (const char* text : {"## Closure vs DEM", "| free-surface angle |", "| surface speed |", "**does not reproduce**",
                           "](closure_vs_dem/surface_angle.png)", "](closure_vs_dem/surface_speed.png)", "3 frames from t = 0.3 s",
                           "this study compares it with the coarse-grained DEM of one platform box"}) {
    INFO(text);
    CHECK(report.find(text) != std::string::npos);
  }
  CHECK(fs::exists(dir / "out/closure_vs_dem/comparison.csv"));
  CHECK(fs::exists(dir / "out/inputs/scenario.yaml"));
}

TEST_CASE("A hold study with a fit reports the calibrated closure on its held-out frames", "[study][hold][closure][fit]") {
  TempDir dir("hold_study_fit");
  grainscale::testing::write_planar_bed_fields(dir / "fields.h5", {0.3, 0.6, 0.9, 1.2, 1.5, 1.8, 2.1}, 0.03, 0.05, 0.0);
  write_text(dir / "still.yaml", box_yaml("still", 2));
  write_text(dir / "study.yaml", "kind: hold\nname: fitted\nscenarios:\n  - {file: still.yaml, end: 8}\n"
                                 "validate: {cg_fields: fields.h5, dem_scenario: " + std::string(GRAINSCALE_SOURCE_DIR) +
                                     "/studies/platform_quick/scenario.yaml, material_from: still, measure_depth: 0.02, fit: {train_until: 1.0, "
                                     "parameters: [basal_friction_deg]}}\n"
                                 "output: {directory: out}\n");
  std::string report_path;
  const studies::HoldStudyResults r =
      studies::run_hold_study(studies::load_hold_study_settings(dir / "study.yaml"), studies::StudyOptions{}, report_path);
  REQUIRE(r.validation);
  REQUIRE(r.validation->fit);
  CHECK(r.validation->measure_depth == 0.02);
  CHECK(r.validation->fit->names == std::vector<std::string>{"basal_friction_deg"});
  CHECK(r.validation->fit->fitted_train.frames == 3);  // 0.3, 0.6, 0.9 s
  CHECK(r.validation->fit->fitted_test.frames == 4);
  const std::string report = slurp(report_path);
  for (const char* text : {"### The closure's bed friction calibrated on the early frames", "| basal_friction_deg |",
                           "| fitted, test (held out) | 4 |", "Verdict on the held-out frames"}) {
    INFO(text);
    CHECK(report.find(text) != std::string::npos);
  }
  CHECK(slurp(dir / "out/closure_vs_dem/comparison.csv").find("fitted_surface_angle_deg,fitted_surface_speed_m_s,block") !=
        std::string::npos);
}

TEST_CASE("The report's coverage pair means 8.7 times the visible chaff at the ends", "[study][hold]") {
  // coverage = 1 - exp(-k m): m_end / m_centre = ln(1 - 0.6) / ln(1 - 0.1), whatever k is.
  CHECK(studies::report_visible_chaff_ratio() == Approx(8.6967).epsilon(1e-4));
  for (double k : {1.0, 37.0, 500.0}) {
    const double m_centre = -std::log(1 - 0.1) / k, m_end = m_centre * studies::report_visible_chaff_ratio();
    CHECK(1 - std::exp(-k * m_end) == Approx(0.6).epsilon(1e-12));
  }
}

TEST_CASE("Bad hold study files name the file and the key", "[study][hold][input]") {
  TempDir dir("hold_study_bad");
  auto fails_with = [&](const std::string& scenarios_extra, const std::string& extra, const std::string& file,
                        const std::string& needle, const std::string& from = "", const std::string& to = "") {
    write_reduced(dir, scenarios_extra, extra);
    replace_in_file(dir / "study.yaml", from, to);
    require_input_error(dir / "study.yaml", [](const std::string& f) { studies::load_hold_study_settings(f); }, file, needle, scenarios_extra + extra + to);
  };
  fails_with("", "extra_key: 1\n", "study.yaml", "extra_key");
  fails_with("  - {file: rocking.yaml, ends: 5}\n", "", "study.yaml", "scenarios[3].ends");
  fails_with("  - {file: missing.yaml}\n", "", "study.yaml", "scenarios[3].file");
  fails_with("", "", "study.yaml", "scenarios", "scenarios:\n  - {file: still.yaml, end: 20}\n  - {file: rocking.yaml, end: 40, "
             "compare_with_report: true}\n  - {file: rocking_long.yaml, end: 80}\n", "scenarios: []\n");
  fails_with("", "", "study.yaml", "scenarios[0].end", "end: 20}", "end: 500}");  // beyond the file's 400 s
  fails_with("", "", "study.yaml", "scenarios[0].end", "end: 20}", "end: 0}");
  fails_with("  - {file: rocking.yaml}\n", "", "study.yaml", "already used");
  fails_with("", "validate: {cg_fields: still.yaml, dem_scenario: still.yaml, material_from: nowhere}\n", "study.yaml",
             "validate.material_from");
  fails_with("", "validate: {cg_fields: none.h5, dem_scenario: still.yaml, material_from: still}\n", "study.yaml",
             "validate.cg_fields");
  fails_with("", "validate: {cg_fields: still.yaml, dem_scenario: still.yaml, material_from: still, fit: {train_until: -1}}\n",
             "study.yaml", "validate.fit.train_until");
  fails_with("", "validate: {cg_fields: still.yaml, dem_scenario: still.yaml, material_from: still, "
             "fit: {train_until: 5, parameters: [tilt]}}\n", "study.yaml", "validate.fit.parameters");
  fails_with("", "validate: {cg_fields: still.yaml, dem_scenario: still.yaml, material_from: still, fit: {until: 5}}\n",
             "study.yaml", "validate.fit");
  fails_with("", "validate: {cg_fields: still.yaml, dem_scenario: still.yaml, material_from: still, measure_depth: 0}\n",
             "study.yaml", "validate.measure_depth");
  // An error inside a listed scenario names that scenario's file.
  write_text(dir / "broken.yaml", box_yaml("broken", 30) + "typo_key: 1\n");
  fails_with("  - {file: broken.yaml}\n", "", "broken.yaml", "typo_key");
}

TEST_CASE("grainscale study reaches the hold runner through the kind key", "[study][hold][cli]") {
  TempDir dir("hold_study_cli");
  write_reduced(dir);
  CHECK(studies::study_kind_of(dir / "study.yaml").run == &studies::hold_study_runner);
  // The binary: an empty scenario list is the hold reader's error (exit status 2 for input errors).
  write_text(dir / "empty.yaml", "kind: hold\nname: empty\nscenarios: []\noutput: {directory: out}\n");
  const testing::CommandResult r = testing::run_command(std::string(GRAINSCALE_BINARY) + " study " + (dir / "empty.yaml") + " 2>&1");
  const std::string& text = r.output;
  const int status = r.status;
  INFO(text);
  CHECK(WEXITSTATUS(status) == 2);
  CHECK(text.find("empty.yaml") != std::string::npos);
  CHECK(text.find("'scenarios'") != std::string::npos);
  CHECK(text.find("empty") != std::string::npos);
}

TEST_CASE("The shipped closure-sensitivity study loads and differs only in the friction law", "[study][hold][input]") {
  const studies::HoldStudySettings s =
      studies::load_hold_study_settings(std::string(GRAINSCALE_SOURCE_DIR) + "/studies/hold_closure_sensitivity.yaml");
  REQUIRE(s.scenarios.size() == 2);
  // The two closures differ in their friction law only.
  const auto& a = s.scenarios[0].settings.friction;
  const auto& b = s.scenarios[1].settings.friction;
  CHECK(a.internal_deg == b.internal_deg);
  CHECK(a.layer_depth / a.grain_diameter == Approx(10));
  CHECK(b.layer_depth / b.grain_diameter == Approx(2.3));
  CHECK(b.delta_mu == 4.45);
}

TEST_CASE("The rolled deep slice's two closures load and differ only in the friction law", "[study][hold][input]") {
  const std::string dir = std::string(GRAINSCALE_SOURCE_DIR) + "/studies/";
  const studies::HoldSettings a = studies::load_hold_settings(dir + "hold_deep_slice_roll.yaml");
  const studies::HoldSettings b = studies::load_hold_settings(dir + "hold_deep_slice_roll_calibrated.yaml");
  CHECK(a.friction.layer_depth / a.friction.grain_diameter == Approx(10));
  CHECK(b.friction.layer_depth / b.friction.grain_diameter == Approx(2.3));
  CHECK(a.friction.delta_mu == 0.26);
  CHECK(b.friction.delta_mu == 4.45);
  CHECK(a.friction.basal_deg == b.friction.basal_deg);
  CHECK(a.friction.side_walls.friction == b.friction.side_walls.friction);
}
