// The progress line a long run prints (dem/progress.hpp): what a user watching a days-long run reads.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "dem/progress.hpp"

using grainscale::dem::Progress;

TEST_CASE("A progress line gives the time, the share done, the step, the speeds and the ETA", "[dem][progress]") {
  // 1 simulated s per wall-clock hour, 2 M sphere-steps/s, 1 h 1 min 1 s to go.
  CHECK(Progress::line(1.0, 2.0, 0.5, 1e-5, 1.0 / 3600, 2e6, 3661) ==
        "t = 1 / 2 s ( 50.0 %) | step 1e-05 s | 1 sim s per wall h | 2 M sphere-steps/s | ETA 1:01:01");
  // No step given (a caller with none to show), an unknown ETA.
  CHECK(Progress::line(0.25, 2.0, 0.125, 0, 0, 0, -1) ==
        "t = 0.25 / 2 s ( 12.5 %) | 0 sim s per wall h | 0 M sphere-steps/s | ETA --:--:--");
}

TEST_CASE("A run's progress line shows the step it takes now, which the step control changes", "[dem][progress]") {
  std::vector<std::string> lines;
  Progress progress(0.0, 1.0, 0.0, [&](const std::string& l) { lines.push_back(l); });
  progress.update(0.1, 100, 10, true, 1.0e-5);
  progress.update(0.2, 200, 10, true, 6.01143e-6);  // lowered by the control
  progress.update(0.3, 300, 10, true);              // a caller that shows none
  REQUIRE(lines.size() == 3);
  CHECK(lines[0].find("| step 1e-05 s |") != std::string::npos);
  CHECK(lines[1].find("| step 6.011e-06 s |") != std::string::npos);
  CHECK(lines[2].find("| step ") == std::string::npos);
  CHECK(lines[2].rfind("t = 0.3 / 1 s ( 30.0 %) |", 0) == 0);
}
