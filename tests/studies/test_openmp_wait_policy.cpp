// How grainscale's OpenMP threads wait (studies/openmp_wait_policy.hpp): a long spin on an idle
// machine, the short one where other work is runnable or the load is unknown.
#include <catch2/catch.hpp>
#include <string>

#include "studies/openmp_wait_policy.hpp"

using namespace grainscale::studies;

TEST_CASE("OpenMP threads spin long only on an idle machine", "[studies][openmp]") {
  CHECK(std::string(spin_count_for(1)) == kIdleSpinCount);     // only this program runnable
  CHECK(std::string(spin_count_for(2)) == kDefaultSpinCount);  // another task wants a core
  CHECK(std::string(spin_count_for(9)) == kDefaultSpinCount);
  CHECK(std::string(spin_count_for(0)) == kDefaultSpinCount);  // /proc/loadavg unreadable: shared
  CHECK(std::stol(kIdleSpinCount) > std::stol(kDefaultSpinCount));
}
