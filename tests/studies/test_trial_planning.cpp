// `grainscale study` with kind trial_planning (studies/trial_planning_study.hpp): a reduced sweep runs
// end to end through the kinds table and its report has every section; the discrimination score picks
// the trial that really separates two variants and finds none when the variants are identical;
// variants are read from a loop.yaml by their BIC and constraint; 1 and 2 threads give the same bytes;
// bad study files name the file and the key.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "dem/input_error.hpp"
#include "studies/study_kinds.hpp"
#include "studies/trial_discrimination.hpp"
#include "studies/trial_plan_settings.hpp"
#include "studies/trial_variants.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale;
using grainscale::testing::slurp;
using grainscale::testing::TempDir;
using grainscale::testing::write_text;
namespace fs = std::filesystem;

namespace {

/// A 0.4 m box, 20 mm of grain on 10 x 4 chaff cells, a fast platform (3 s cycle), 30 s of motion.
void write_reduced(const TempDir& dir, const std::string& variants, const std::string& sweep = "",
                   const std::string& extra = "") {
  write_text(dir / "base.yaml", R"(name: small
container: {length: 0.4, depth: 0.1, fill_height: 0.02, pivot: [-0.3, -0.2], nx: 10}
motion: {type: platform, amplitude_deg: 24, frequency: 0.5, pause: 0.5, axis: [0, 1, 0]}
material: {internal_friction_deg: 23.1, basal_friction_deg: 14, delta_mu: 0.26, grain_diameter: 6.7e-3, flowing_layer_diameters: 3}
chaff:
  window: 0.02
  nz: 4
  initial: 0.1
  terms:
    advection: {limiter: van_leer}
    segregation: {S: 1.0e-3, limiter: van_leer}
    shear_diffusion: {C: 0.04, d: 6.7e-3}
    background_diffusion: {D0: 1.0e-8}
time: {end: 30}
output: {folder: unused}
)");
  write_text(dir / "study.yaml", R"(kind: trial_planning
name: reduced
base: base.yaml
motions:
  rock: {motion: {type: sinusoids, pitch: {amplitude_deg: 10, period: 2}}, pivot: [0, -0.5], pivot_from: centre}
sweep:
)" + (sweep.empty() ? std::string("  - {length: [0.3, 0.6], period: [3, 5]}\n  - {motion: [rock], length: [0.4]}\n") : sweep) +
                                         R"(time: {duration: 30}
observation: {kappa: 272, delta: 0.0067}
variants:
)" + variants + R"(discrimination: {sigma: {centre: 0.05, ends: 0.1}}
output: {directory: out}
)" + extra);
}

const std::string kTwoVariants = R"(  list:
    - {name: base}
    - {name: drift, effect: surface_drift, parameters: {surface_drift.U: 1.0e-3, observation.kappa: 300}}
)";

std::string run_study(const TempDir& dir, int threads, const std::string& out) {
  studies::StudyOptions o;
  o.threads = threads;
  o.output_override = dir / out;
  const studies::StudyKind& kind = studies::study_kind_of(dir / "study.yaml");
  CHECK(std::string(kind.name) == "trial_planning");
  return kind.run(dir / "study.yaml", o);
}

}  // namespace

TEST_CASE("The reduced trial-planning study runs end to end and its report has every section", "[study][trial]") {
  TempDir dir("trial");
  write_reduced(dir, kTwoVariants);
  const std::string report_path = run_study(dir, 2, "out");
  const std::string out = dir / "out";
  const std::string report = slurp(report_path);
  for (const char* section : {"## What was run", "## 1. The sweep", "## 2. Ranking by predicted congregation",
                              "## 3. Model variants compared", "## 4. Recommended trials", "## Limits"}) {
    INFO(section);
    CHECK(report.find(section) != std::string::npos);
  }
  for (const char* png : {"congregation_length.png", "congregation_period.png", "congregation_motion.png",
                          "congregation_map.png", "discrimination_length.png", "trial_1.png"}) {
    INFO(png);
    CHECK(fs::exists(out + "/" + png));
    CHECK(report.find(png) != std::string::npos);
  }
  for (const char* f : {"predictions.csv", "ranking.csv", "discrimination.csv", "summary.yaml", "log.txt",
                        "inputs/study.yaml", "inputs/base.yaml"}) {
    INFO(f);
    CHECK(fs::exists(out + "/" + f));
  }
  // 5 designs x 2 variants, every case ran and conserved chaff.
  const std::string csv = slurp(out + "/predictions.csv");
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 2 + 10);
  CHECK(csv.find("nan") == std::string::npos);
  const std::string log = slurp(out + "/log.txt");
  CHECK(log.find("ETA") != std::string::npos);
  CHECK(report.find("Warnings") == std::string::npos);
}

TEST_CASE("One and two threads give bitwise-identical trial-planning numbers", "[study][trial]") {
  TempDir dir("trial_threads");
  write_reduced(dir, kTwoVariants);
  run_study(dir, 1, "one");
  run_study(dir, 2, "two");
  for (const char* f : {"predictions.csv", "ranking.csv", "discrimination.csv", "summary.yaml"}) {
    INFO(f);
    const std::string a = slurp(dir / (std::string("one/") + f)), b = slurp(dir / (std::string("two/") + f));
    CHECK(!a.empty());
    CHECK(a == b);
  }
}

TEST_CASE("The discrimination score picks the trial that separates the variants", "[study][trial]") {
  // Two variants that agree everywhere except in long containers, where one puts more chaff at the
  // ends: the chosen trial is the longest container.
  const std::vector<double> lengths = {0.4, 0.8, 1.2, 1.6, 0.6};
  std::vector<std::vector<studies::PredictedObservation>> p;
  for (double L : lengths) {
    const studies::PredictedObservation a{0.3, 0.2, 0.3};
    studies::PredictedObservation b = a;
    if (L > 1.0) b.left = b.right = 0.3 + 0.25 * (L - 1.0);  // 0.05 at 1.2 m, 0.15 at 1.6 m
    p.push_back({a, b});
  }
  studies::DiscriminationSettings s;
  s.sigma_end = 0.05;
  s.sigma_centre = 0.05;
  s.top = 2;
  const auto ranked = studies::score_trials(p, s);
  REQUIRE(ranked.size() == lengths.size());
  CHECK(lengths[ranked[0].design] == 1.6);
  CHECK(ranked[0].score == Approx(std::sqrt(2.0) * 0.15 / 0.05));
  CHECK(ranked.back().score == 0);
  const auto rec = studies::recommended_trials(ranked, s);
  REQUIRE(rec.size() == 1);  // 1.2 m separates by sqrt(2) sigma only, below 2
  CHECK(lengths[rec[0].design] == 1.6);

  // A third variant equal to the first: "min" over pairs is 0 everywhere, "mean" is not.
  for (auto& row : p) row.push_back(row[0]);
  CHECK(studies::score_trials(p, s)[0].score == 0);
  CHECK(studies::recommended_trials(studies::score_trials(p, s), s).empty());
  s.score = "mean";
  CHECK(lengths[studies::score_trials(p, s)[0].design] == 1.6);
}

TEST_CASE("Identical variants give score 0 and no trial discriminates", "[study][trial]") {
  TempDir dir("trial_same");
  write_reduced(dir, R"(  list:
    - {name: one, effect: surface_drift, parameters: {surface_drift.U: 1.0e-3}}
    - {name: two, effect: surface_drift, parameters: {surface_drift.U: 1.0e-3}}
)", "  {length: [0.3, 0.6]}\n");
  const std::string report = slurp(run_study(dir, 2, "out"));
  CHECK(report.find("**No trial discriminates**") != std::string::npos);
  const std::string csv = slurp(dir / "out/discrimination.csv");
  CHECK(csv.find(",0,0,0,one,two") != std::string::npos);
  CHECK(slurp(dir / "out/summary.yaml").find("discriminating_trials: []") != std::string::npos);
}

TEST_CASE("Trial-planning variants come from a loop.yaml by BIC and constraint", "[study][trial]") {
  TempDir dir("trial_loop");
  write_text(dir / "loop.yaml", R"(base:
  parameters:
    observation.kappa: {value: 270, standard_error: 60}
  bic: 21
candidates:
  - {name: surface_drift, ok: true, bic: 2.3,
     parameters: {observation.kappa: {value: 300, standard_error: 80}, surface_drift.U: {value: 3.2e-4, standard_error: 1.2e-4}}}
  - {name: wall_mobility, ok: true, bic: 6.3,
     parameters: {observation.kappa: {value: 231, standard_error: 59}, wall_mobility.W: {value: 0.99, standard_error: 345}}}
  - {name: lever_arm, ok: true, bic: 22.4,
     parameters: {observation.kappa: {value: 270, standard_error: 60}, lever_arm.S: {value: 1.0e-3, standard_error: 1.0e-4}}}
  - {name: pause_creep, ok: false, bic: .nan, parameters: {}}
chosen: none
reason: "nothing qualified"
)");
  const studies::LoopVariants v = studies::variants_from_loop(dir / "loop.yaml", 10, true);
  REQUIRE(v.variants.size() == 2);
  CHECK(v.variants[0].name == "surface_drift");  // the best BIC first
  CHECK(v.variants[0].effect == "surface_drift");
  CHECK(v.variants[0].delta_bic == 0);
  CHECK(v.variants[0].parameters[1].first == "surface_drift.U");
  CHECK(v.variants[0].parameters[1].second == 3.2e-4);
  CHECK(v.variants[1].name == "base");  // 18.7 above the best, but the loop's choice
  CHECK(v.variants[1].delta_bic == Approx(21 - 2.3));
  REQUIRE(v.excluded.size() == 3);
  CHECK(v.excluded[0].name == "pause_creep");
  CHECK(v.excluded[1].name == "wall_mobility");  // within 10 of the best but unconstrained
  CHECK(v.excluded[2].name == "lever_arm");      // 20 above the best
  CHECK(studies::variants_from_loop(dir / "loop.yaml", 10, false).variants.size() == 3);

  // And through a study file: the variants carry into the settings.
  write_reduced(dir, "  loop: {file: loop.yaml, max_delta_bic: 10}\n");
  const studies::TrialPlanSettings s = studies::load_trial_plan_settings(dir / "study.yaml");
  CHECK(s.variants.size() == 2);
  CHECK(s.designs.size() == 5);
  CHECK(s.swept == std::vector<std::string>{"motion", "length", "amplitude_deg", "period"});
}

TEST_CASE("Bad trial-planning study files name the file and the key", "[study][trial][input]") {
  TempDir dir("trial_bad");
  auto fails_with = [&](const std::string& variants, const std::string& sweep, const std::string& extra,
                        const std::string& needle) {
    write_reduced(dir, variants, sweep, extra);
    INFO(needle);
    try {
      (void)studies::load_trial_plan_settings(dir / "study.yaml");
      FAIL("no InputError");
    } catch (const InputError& e) {
      const std::string m = e.what();
      INFO(m);
      CHECK(m.find("study.yaml") != std::string::npos);
      CHECK(m.find(needle) != std::string::npos);
    }
  };
  fails_with(kTwoVariants, "", "colour: red\n", "unknown key 'colour'");
  fails_with(kTwoVariants, "  {length: []}\n", "", "sweep.length': an empty axis");
  fails_with(kTwoVariants, "  - {fill_height: [0.02, 0.5]}\n", "", "sweep[0].fill_height' item 1 = 0.5 is out of range");
  fails_with(kTwoVariants, "  {amplitude_deg: [95]}\n", "", "sweep.amplitude_deg");
  fails_with(kTwoVariants, "  {period: [0.8]}\n", "", "period: 0.8 s must exceed the platform's two pauses");
  fails_with(kTwoVariants, "  {motion: [train]}\n", "", "'train' is not allowed");
  fails_with("  list:\n    - {name: a, effect: gravity_waves, parameters: {gravity_waves.k: 1}}\n", "", "",
             "variants.list[0]': unknown effect 'gravity_waves'");
  fails_with("  list:\n    - {name: a, effect: surface_drift}\n", "", "", "needs its strength 'surface_drift.U'");
  fails_with("  list:\n    - {name: a, parameters: {segregation.S: 5}}\n", "", "", "key 'segregation.S' = 5 is out of range");
  fails_with("  list:\n    - {name: a, parameters: {grain.S: 1}}\n", "", "", "'grain.S' names no term");
  fails_with("  list:\n    - {name: a}\n    - {name: a}\n", "", "", "variant name 'a' used twice");
  fails_with("  {}\n", "", "", "no variant");
}
