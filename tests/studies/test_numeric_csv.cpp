// Reading numeric CSV back: what the stages write parses exactly, and every malformed input is an
// InputError naming the file, the line and the column.
#include <catch2/catch.hpp>

#include <cmath>

#include "dem/input_error.hpp"
#include "studies/numeric_csv.hpp"

using namespace grainscale;
using namespace grainscale::studies;

TEST_CASE("Numeric CSV parses header, numbers, nan, comments and CRLF", "[studies][csv]") {
  const NumericCsv t = NumericCsv::parse(
      "# measured profile\r\nt_s, x_m ,coverage\r\n0,0.025000000000000001,nan\r\n\r\n+1.5,-2e-3,0.25\n", "p.csv");
  CHECK(t.columns() == std::vector<std::string>{"t_s", "x_m", "coverage"});
  REQUIRE(t.rows() == 2);
  CHECK(t.column("x_m")[0] == 0.025000000000000001);
  CHECK(t.column("t_s")[1] == 1.5);
  CHECK(t.column("x_m")[1] == -2e-3);
  CHECK(std::isnan(t.column("coverage")[0]));
  CHECK(t.has("coverage"));
  CHECK(!t.has("c"));
}

TEST_CASE("Malformed numeric CSV names file, line and column", "[studies][csv]") {
  CHECK_THROWS_WITH(NumericCsv::parse("a,b\n1,2\n3,x4\n", "d.csv"),
                    Catch::Contains("d.csv:3") && Catch::Contains("column 'b'") && Catch::Contains("'x4' is not a number"));
  CHECK_THROWS_WITH(NumericCsv::parse("a,b\n1,2,3\n", "d.csv"), Catch::Contains("d.csv:2: 3 values for 2 columns"));
  CHECK_THROWS_WITH(NumericCsv::parse("a,b\n1,\n", "d.csv"), Catch::Contains("column 'b': '' is not a number"));
  CHECK_THROWS_WITH(NumericCsv::parse("a,a\n", "d.csv"), Catch::Contains("appears twice"));
  CHECK_THROWS_WITH(NumericCsv::parse("# only a comment\n", "d.csv"), Catch::Contains("no header"));
  CHECK_THROWS_WITH(NumericCsv::parse("a,b\n1,2\n", "d.csv").column("c"),
                    Catch::Contains("no column 'c'") && Catch::Contains("a, b"));
  CHECK_THROWS_AS(NumericCsv::load("/nonexistent/dir/file.csv"), InputError);
  CHECK_THROWS_AS(NumericCsv::parse("a\n1.5.2\n", "d.csv"), InputError);
}
