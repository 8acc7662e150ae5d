// `grainscale study`: the reduced variant of the default study (studies/platform_quick.yaml) runs
// every stage end to end and its report has every section; the stage files it writes run alone;
// bad study files are errors naming the file and the key, found before the DEM runs.
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "coarsegrain/cg_settings.hpp"
#include "continuum/settings.hpp"
#include "dem/input_error.hpp"
#include "grainscale_version.hpp"
#include "studies/fit_command.hpp"
#include "studies/study_kinds.hpp"
#include "studies/study_run.hpp"
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

const std::string kStudies = std::string(GRAINSCALE_SOURCE_DIR) + "/studies";

/// `grainscale bench ARGS`, which must succeed: its output, and the fingerprint of the last state it
/// timed (one per thread count; a run ends in the same state on any).
std::pair<std::string, std::string> run_bench(const std::string& args) {
  const std::string cmd = std::string(GRAINSCALE_BINARY) + " bench " + args + " 2>&1";
  const testing::CommandResult r = testing::run_command(cmd);
  INFO(cmd << "\n" << r.output);
  REQUIRE(r.status == 0);
  const std::size_t at = r.output.rfind("fingerprint ");
  REQUIRE(at != std::string::npos);
  return {r.output, r.output.substr(at + 12, 16)};
}

/// The default study's stage files, shrunk: 25 clumps and 20 flakes in the same box, a fast
/// half-second tilt, a one-minute prediction.
void write_reduced_study(const TempDir& dir, const std::string& study_extra = "") {
  write_text(dir / "scenario.yaml", "name: reduced\nseed: 3\nmaterials: " + kStudies + "/materials/report_table1.yaml\n" +
                                        R"(scale_factor: 2
contact: {rolling: constant_torque, max_overlap: 0.7}
time: {end: 0.5, pour_interval: 0.005, step_fraction: 0.2}
walls:
  - {name: box, type: box_mesh, min: [0, 0, 0], max: [0.3, 0.03, 0.1], open: [+z], material: perspex,
     pivot: [-0.6, 0.015, -0.3],
     motion: {type: platform, amplitude_deg: 10, frequency: 1.0, pause: 0.05, axis: [0, 1, 0], start_time: 0.1}}
particles:
  - {material: barley, shape: )" + kStudies + R"(/shapes/wheat.yaml, mass: 0.01, rate: 1.0,
     region: {min: [0.005, 0.003, 0.003], max: [0.295, 0.027, 0.045]}}
  - {material: chaff, shape: )" + kStudies + R"(/shapes/chaff.yaml, mass: 0.0001, rate: 0.01,
     region: {min: [0.005, 0.003, 0.003], max: [0.295, 0.027, 0.045]}}
output: {directory: unused, snapshot_interval: 0.05, progress_interval: 100}
)");
  fs::copy_file(kStudies + "/platform_quick/cg.yaml", dir / "cg.yaml", fs::copy_options::overwrite_existing);
  fs::copy_file(kStudies + "/platform_quick/continuum.yaml", dir / "continuum.yaml", fs::copy_options::overwrite_existing);
  write_text(dir / "study.yaml", R"(name: reduced
title: "Reduced default study"
dem: {scenario: scenario.yaml}
cg: {settings: cg.yaml, flow_from: 0.1}
fit:
  model: continuum.yaml
  parameters: [S, kappa]
  data: {from: 0.1, every: 2, min_solid_fraction: 0.1}   # a bed one grain deep
  max_iterations: 5
predict: {end: 60, outputs: 3}
compare: {end_length: 0.05}
output: {directory: out}
)" + study_extra);
}

}  // namespace

TEST_CASE("The reduced default study runs every stage and reports every section", "[study]") {
  TempDir dir("study");
  write_reduced_study(dir);
  studies::StudyOptions o;
  o.threads = 2;
  studies::StudyRun run(studies::load_study_settings(dir / "study.yaml"), o);
  run.setup();
  run.run();
  run.output();
  const std::string out = dir / "out";

  const std::string report = slurp(out + "/report.md");
  for (const char* section : {"## What was run", "## 1. DEM", "## 2. Coarse-graining", "## 3. Fit", "## 4. Prediction",
                              "## 5. Comparison with the measurements", "## Limits of this comparison", "Verdict:"}) {
    INFO(section);
    CHECK(report.find(section) != std::string::npos);
  }
  // Every figure the report names exists.
  for (const char* png : {"cg/slices.png", "cg/coverage.png", "fit/coverage.png", "predict/coverage.png",
                          "predict/coverage_time.png"}) {
    INFO(png);
    CHECK(fs::exists(out + "/" + png));
    CHECK(report.find(png) != std::string::npos);
  }
  // The 30 mm box is about two 2x grains wide: the DEM says so, and the report carries it.
  CHECK(report.find("mm wide, only") != std::string::npos);
  CHECK(fs::exists(out + "/dem/snapshots.xmf"));
  CHECK(fs::exists(out + "/cg/fields.xmf"));
  CHECK(fs::exists(out + "/log.txt"));
  CHECK(fs::exists(out + "/inputs/study.yaml"));
  CHECK(fs::exists(out + "/inputs/scenario.yaml"));

  const studies::StudyResults& r = run.results();
  REQUIRE(r.stages.size() == 4);
  CHECK(r.t0 == Approx(0.1).margin(1e-4));  // the snapshot nearest the motion start (a step either side)
  CHECK(r.initial_c > 0);
  CHECK(r.initial_c < 1);
  CHECK(r.fit_names == std::vector<std::string>{"segregation.S", "observation.kappa"});
  // The prediction conserves chaff and keeps c in [0, 1].
  CHECK(std::fabs(r.chaff_final - r.chaff_initial) <= 1e-10 * r.chaff_initial);
  CHECK(r.c_min >= 0);
  CHECK(r.c_max <= 1);

  // The stage files run alone: each loads with its own loader.
  CHECK_NOTHROW(cg::load_cg_settings(out + "/stages/cg.yaml"));
  CHECK_NOTHROW(cg::load_cg_settings(out + "/stages/cg_flow.yaml"));
  CHECK_NOTHROW(studies::load_fit_command_settings(out + "/stages/fit.yaml"));
  const continuum::ContinuumSettings p = continuum::load_continuum_settings(out + "/stages/predict.yaml");
  CHECK(p.t_end == 60);
  CHECK(p.flow.type == "file");
}

TEST_CASE("Bad study files name the file and the key before anything runs", "[study][input]") {
  TempDir dir("study_bad");
  auto fails_with = [&](const std::string& extra, const std::string& needle, const std::string& replace_from = "",
                        const std::string& replace_to = "") {
    write_reduced_study(dir, extra);
    replace_in_file(dir / "study.yaml", replace_from, replace_to);
    require_input_error(dir / "study.yaml", [](const std::string& f) { studies::load_study_settings(f); }, "study.yaml", needle, extra + replace_to);
  };
  fails_with("extra_key: 1\n", "extra_key");
  fails_with("", "scenario", "scenario: scenario.yaml", "scenario: missing.yaml");
  fails_with("", "parameters", "parameters: [S, kappa]", "parameters: [S, no_such_parameter]");
  fails_with("", "every", "every: 2", "every: 0");
  fails_with("", "flow_to", "flow_from: 0.1}", "flow_from: 0.1, flow_to: 0.05}");
  fails_with("", "end", "end: 60", "end: -1");
  fails_with("", "name", "name: reduced", "name: a/b");
}

TEST_CASE("A study file's kind picks its runner; an unknown kind names the file, the key and the kinds", "[study][input]") {
  TempDir dir("study_kind");
  write_reduced_study(dir);
  CHECK(std::string(studies::study_kind_of(dir / "study.yaml").name) == "platform");
  write_reduced_study(dir, "kind: platform\n");
  CHECK(std::string(studies::study_kind_of(dir / "study.yaml").name) == "platform");
  CHECK_NOTHROW(studies::load_study_settings(dir / "study.yaml"));
  write_reduced_study(dir, "kind: nonsense\n");
  try {
    studies::study_kind_of(dir / "study.yaml");
    FAIL("no error for an unknown kind");
  } catch (const InputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("study.yaml") != std::string::npos);
    CHECK(what.find("kind") != std::string::npos);
    CHECK(what.find("platform") != std::string::npos);
  }
}

TEST_CASE("grainscale COMMAND --help prints that command's usage", "[study][cli]") {
  for (const std::string cmd : {"study", "dem", "cg", "fit", "predict", "loop", "calibrate", "hold"}) {
    INFO(cmd);
    const testing::CommandResult r = testing::run_command(std::string(GRAINSCALE_BINARY) + " " + cmd + " --help");
    const std::string& out = r.output;
    CHECK(r.status == 0);
    CHECK(out.rfind("usage: grainscale " + cmd + " ", 0) == 0);
    CHECK(out.find("(all commands: grainscale --help)") != std::string::npos);
  }
}

TEST_CASE("grainscale version names the revision and the build the benchmarks' figures come from", "[study][cli]") {
  // bench/lib_bench.sh writes this line first in every results.txt. This test is compiled with the
  // flags of the binary (CMakeLists.txt), so its macros say what the line must say.
  const testing::CommandResult r = testing::run_command(std::string(GRAINSCALE_BINARY) + " version");
  const std::string& out = r.output;
  CHECK(r.status == 0);
  CHECK(out.rfind("grainscale ", 0) == 0);
  CHECK(out.find(std::string("(") + git_revision + ")") != std::string::npos);
#if defined(__clang__)
  CHECK(out.find("Clang ") != std::string::npos);
#elif defined(__GNUC__)
  CHECK(out.find(std::string("GCC ") + __VERSION__) != std::string::npos);
#endif
#if defined(__AVX512F__)
  CHECK(out.find(", x86-64 with AVX-512,") != std::string::npos);
#elif defined(__AVX2__)
  CHECK(out.find(", x86-64 with AVX2,") != std::string::npos);
#elif defined(__x86_64__)
  CHECK(out.find(", x86-64 without AVX2,") != std::string::npos);
#endif
#if defined(__OPTIMIZE__)
  CHECK(out.find(", optimised,") != std::string::npos);
#else
  CHECK(out.find(", not optimised") != std::string::npos);
#endif
#if defined(NDEBUG)
  CHECK(out.find(", assertions off") != std::string::npos);
#else
  CHECK(out.find(", assertions on") != std::string::npos);
#endif
}

TEST_CASE("grainscale names a bad number in an option (--steps, --warmup, --threads, --density, --mass) and the allowed range", "[study][cli][input]") {
  struct Case {
    const char* args;
    const char* message;
  };
  for (const Case c : {Case{"bench unused.yaml --warmup -1", "--warmup must be 0 or more"},
                       Case{"bench unused.yaml --warmup many", "--warmup: 'many' is not a whole number"},
                       Case{"bench unused.yaml --steps 0", "--steps must be at least 1"},
                       Case{"bench unused.yaml --steps 10x", "--steps: '10x' is not a whole number"},
                       Case{"bench unused.yaml --large-bed-from -1", "--large-bed-from must be 0 or more"},
                       Case{"bench unused.yaml --large-bed-from 5e4", "--large-bed-from: '5e4' is not a whole number"},
                       Case{"dem unused.yaml --threads 1,2x", "--threads: '2x' is not a whole number"},
                       Case{"dem unused.yaml --threads 0", "--threads: counts must be in [1, 1024]"},
                       Case{"study unused.yaml --threads 2x", "--threads: '2x' is not a whole number"},
                       Case{"calibrate unused.yaml --threads 0", "--threads: counts must be in [1, 1024]"},
                       Case{"shape unused.yaml --density 1000kg", "--density: '1000kg' is not a number"},
                       Case{"shape unused.yaml --mass -1", "--mass must be positive"}}) {
    INFO(c.args);
    const testing::CommandResult r = testing::run_command(std::string(GRAINSCALE_BINARY) + " " + c.args + " 2>&1");
    INFO(r.output);
    CHECK(r.status != 0);
    CHECK(r.output.find(c.message) != std::string::npos);
  }
}

TEST_CASE("grainscale bench --large-bed-from 0 times the force loop's large-bed path, with the same numbers",
          "[study][cli][bench]") {
  // The reduced study's bed (a few thousand spheres) takes the in-cache path by default; from 0
  // spheres on it takes the path for beds beyond the caches, which must end in the same state.
  const TempDir dir("bench_path");
  write_reduced_study(dir);
  std::string scenario = testing::slurp(dir / "scenario.yaml");
  const std::string end = "time: {end: 0.5,";
  REQUIRE(scenario.find(end) != std::string::npos);
  scenario.replace(scenario.find(end), end.size(), "time: {end: 0.05,");
  testing::write_text(dir / "short.yaml", scenario);
  auto bench = [&](const std::string& extra) {
    return run_bench(dir / "short.yaml --settled " + dir / "settled.h5 --steps 30 --warmup 0 --threads 1,2" + extra);
  };
  const auto [plain_log, plain] = bench("");
  CHECK(plain_log.find("force loop: the in-cache path (from 50000 spheres on)") != std::string::npos);
  const auto [large_log, large] = bench(" --large-bed-from 0");
  CHECK(large_log.find("force loop: the large-bed path (from 0 spheres on)") != std::string::npos);
  CHECK(large == plain);
}

TEST_CASE("grainscale bench --from settles on from an earlier state of the bed, bit for bit as settling straight through",
          "[study][cli][bench]") {
  // The reduced study's bed, poured and then tilting from 0.1 s: settled to 0.12 s and kept, then
  // continued from there to 0.2 s; against settling to 0.2 s in one go. The timed steps from either
  // settled state must end in the same state (bench prints its fingerprint).
  const TempDir dir("bench_from");
  write_reduced_study(dir);
  const std::string scenario = testing::slurp(dir / "scenario.yaml");
  const std::string end = "time: {end: 0.5,";
  REQUIRE(scenario.find(end) != std::string::npos);
  auto with_end = [&](const std::string& name, const std::string& t) {
    std::string s = scenario;
    s.replace(s.find(end), end.size(), "time: {end: " + t + ",");
    testing::write_text(dir / name, s);
  };
  with_end("early.yaml", "0.12");
  with_end("later.yaml", "0.2");
  auto bench = [&](const std::string& args) { return run_bench(args + " --steps 20 --warmup 0 --threads 1"); };
  bench(dir / "early.yaml --settled " + dir / "early.h5");
  const auto [continued_log, continued] = bench(dir / "later.yaml --from " + dir / "early.h5 --settled " + dir / "later.h5");
  CHECK(continued_log.find("starting from") != std::string::npos);
  CHECK(continued_log.find("settled for 0.2 s") != std::string::npos);
  const auto [straight_log, straight] = bench(dir / "later.yaml --settled " + dir / "straight.h5");
  CHECK(continued == straight);
  // A kept settled state is read as before (--from then unused), and a missing one is named.
  const auto [again_log, again] = bench(dir / "later.yaml --from " + dir / "early.h5 --settled " + dir / "later.h5");
  CHECK(again == continued);
  CHECK(again_log.find("not used") != std::string::npos);
  const std::string missing = dir / "missing.h5";
  const testing::CommandResult r =
      testing::run_command(std::string(GRAINSCALE_BINARY) + " bench " + dir / "later.yaml --from " + missing + " 2>&1");
  CHECK(r.status != 0);
  CHECK(r.output.find("--from: " + missing + " is not a file") != std::string::npos);
}
