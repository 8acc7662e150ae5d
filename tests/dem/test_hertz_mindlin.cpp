#include <catch2/catch.hpp>
#include "dem/contact/hertz_mindlin.hpp"
TEST_CASE("placeholder", "[dem]") { REQUIRE(true); }
