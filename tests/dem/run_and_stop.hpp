#pragma once
// `grainscale dem` runs for the tests: one run to its end (or resumed to it), and one stopped dead
// right after its nth checkpoint, as a kill would stop it. Used by test_resume.cpp and
// test_step_control.cpp.
#include <catch2/catch.hpp>
#include <string>

#include "dem/dem_run.hpp"

namespace grainscale::dem::testing {

/// Thrown from the checkpoint hook: ends the run as abruptly as a kill (nothing after it runs).
struct Killed {};

inline void run_to_end(const std::string& scenario, const std::string& out, bool resume = false) {
  DemRun r(scenario, out, resume);
  r.setup();
  r.run();
  r.output();
}

/// Run until the `n`th checkpoint has been written, then stop dead.
inline void run_until_checkpoint(const std::string& scenario, const std::string& out, int n) {
  DemRun r(scenario, out);
  int written = 0;
  r.on_checkpoint([&](const std::string&) {
    if (++written == n) throw Killed{};
  });
  r.setup();
  CHECK_THROWS_AS(r.run(), Killed);
}

}  // namespace grainscale::dem::testing
