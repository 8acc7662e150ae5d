#pragma once
// Runs a shell command and returns what it printed and how it ended: for the tests that run the
// grainscale binary (the command line adds "2>&1" where its errors are to be read too).
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>

namespace grainscale::testing {

struct CommandResult {
  std::string output;  // its standard output
  int status = -1;     // as pclose returns it: 0 for success, WEXITSTATUS(status) the exit code
};

inline CommandResult run_command(const std::string& command) {
  FILE* p = popen(command.c_str(), "r");
  REQUIRE(p != nullptr);
  CommandResult r;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) r.output += buf;
  r.status = pclose(p);
  return r;
}

}  // namespace grainscale::testing
