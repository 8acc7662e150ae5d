// `kind: loop` studies (studies/loop_study*.cpp): a reduced variant (the report's wheat coverage with one
// candidate) runs end to end, its report has every section and says why three points justify nothing;
// bad study files name the file and the key; `grainscale study` reaches the loop runner through the
// file's kind. (The loop's own finding of hidden effects is tested in test_loop.cpp.)
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "dem/input_error.hpp"
#include "studies/loop_study.hpp"
#include "studies/study_kinds.hpp"
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

const std::string kData = std::string(GRAINSCALE_SOURCE_DIR) + "/studies/data";

void write_reduced(const TempDir& dir, const std::string& extra = "") {
  write_text(dir / "study.yaml", "kind: loop\nname: reduced_loop\nloop: " + kData + "/wheat_30min_loop.yaml\n" +
                                     "provenance: " + kData + "/README.md\n"
                                     "caveats: [\"Only the right-hand peak is trustworthy.\"]\n"
                                     "candidates: [surface_drift]\n"
                                     "output: {directory: out}\n" + extra);
}

}  // namespace

TEST_CASE("The reduced loop study runs the loop on the report's coverage and reports every section", "[study][loop]") {
  TempDir dir("loop_study");
  write_reduced(dir);
  const studies::LoopStudySettings s = studies::load_loop_study_settings(dir / "study.yaml");
  REQUIRE(s.loop.candidates.size() == 1);
  std::string report_path;
  const studies::LoopStudyResults r = studies::run_loop_study(s, studies::StudyOptions{}, report_path);
  const std::string out = dir / "out";
  const std::string report = slurp(report_path);
  for (const char* section : {"## What was run", "## Warnings", "## 1. The data and where they come from",
                              "## 2. The base model's fit", "## 3. Diagnosis of the residual",
                              "## 4. Candidate effects, ranked", "## 5. The effect added", "Verdict:",
                              "## 6. Error before and after", "## Limits", "Only the right-hand peak is trustworthy.",
                              "inputs/README.md"}) {
    INFO(section);
    CHECK(report.find(section) != std::string::npos);
  }
  for (const char* png : {"loop/before_coverage.png", "loop/ranking.png", "loop/before_regions.png"}) {
    INFO(png);
    CHECK(fs::exists(out + "/" + png));
    CHECK(report.find(std::string("](") + png + ")") != std::string::npos);
  }
  for (const char* f : {"inputs/study.yaml", "inputs/wheat_30min_loop.yaml", "inputs/wheat_30min_fit.yaml",
                        "inputs/wheat_30min_model.yaml", "inputs/wheat_30min_coverage.csv", "inputs/README.md",
                        "inputs/platform_box_demo.yaml", "loop/loop.yaml", "loop/report.md", "log.txt"}) {
    INFO(f);
    CHECK(fs::exists(out + "/" + f));
  }
  // Three points, one time, x blocks of one point: nothing can be cross-validated, so nothing is
  // added, and the report says why and what the data cannot do.
  CHECK(r.loop.chosen == -1);
  CHECK(r.loop.data.coverage.size() == 3);
  CHECK(report.find("**Nothing added.**") != std::string::npos);
  CHECK(report.find("**No candidate can be cross-validated**") != std::string::npos);
  CHECK(report.find("One measured profile") != std::string::npos);
  CHECK(report.find("1 observation carries less than 1 %") != std::string::npos);  // the left peak, sigma 1
  // The full-data fit still points at the drift (docs/loop.md: BIC lower by about 19).
  CHECK(report.find("On all the data (no cross-validation) `surface_drift` fits best") != std::string::npos);
}

TEST_CASE("Bad loop study files name the file and the key", "[study][loop][input]") {
  TempDir dir("loop_study_bad");
  auto fails_with = [&](const std::string& extra, const std::string& needle, const std::string& from = "",
                        const std::string& to = "") {
    write_reduced(dir, extra);
    replace_in_file(dir / "study.yaml", from, to);
    require_input_error(dir / "study.yaml", [](const std::string& f) { studies::load_loop_study_settings(f); }, "study.yaml", needle, extra + to);
  };
  fails_with("extra_key: 1\n", "extra_key");
  fails_with("", "'loop'", "wheat_30min_loop.yaml", "no_such_loop.yaml");
  fails_with("", "'provenance'", "README.md", "NO_README.md");
  fails_with("", "'candidates'", "candidates: [surface_drift]", "candidates: []");
  fails_with("", "'candidates'", "candidates: [surface_drift]", "candidates: [no_such_effect]");
  fails_with("", "'caveats'", "caveats: [\"Only the right-hand peak is trustworthy.\"]", "caveats: [\"\"]");
  fails_with("candidate_iterations: 0\n", "candidate_iterations");
  fails_with("", "'output'", "output: {directory: out}\n", "");
}

TEST_CASE("grainscale study reaches the loop runner through the kind key", "[study][loop][cli]") {
  TempDir dir("loop_study_cli");
  write_reduced(dir);
  CHECK(studies::study_kind_of(dir / "study.yaml").run == &studies::loop_study_runner);
  write_reduced(dir, "candidate_iterations: 0\n");
  const testing::CommandResult r = testing::run_command(std::string(GRAINSCALE_BINARY) + " study " + (dir / "study.yaml") + " 2>&1");
  const std::string& text = r.output;
  const int status = r.status;
  INFO(text);
  CHECK(WEXITSTATUS(status) == 2);
  CHECK(text.find("study.yaml") != std::string::npos);
  CHECK(text.find("candidate_iterations") != std::string::npos);
}
