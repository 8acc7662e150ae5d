// Numeric CSV (studies/numeric_csv.hpp) and the fit's data mapping (studies/fit_observations.hpp):
// the input is read as a CSV, every column taken, and then mapped onto a small bed as concentration
// fields (t_s,x_m,z_m,c[,sigma]) and as coverage (t_s,x_m,coverage[,sigma]). Bad input must end in
// InputError.
#include "continuum/grid.hpp"
#include "dem/input_error.hpp"
#include "fuzz_input_file.hpp"
#include "studies/fit_observations.hpp"
#include "studies/numeric_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace grainscale;
  try {
    const studies::NumericCsv csv =
        studies::NumericCsv::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzzed.csv");
    for (const std::string& c : csv.columns()) (void)csv.column(c);
    for (std::size_t r = 0; r < csv.rows(); ++r) (void)csv.line(r);
  } catch (const InputError&) {
  }
  const std::string path = fuzz::input_file(data, size, "fuzzed_data.csv");
  const continuum::Grid grid = continuum::Grid::flat(0.8, 0.1, 8, 4);
  try {
    (void)studies::map_observations({path, "", 0.01, std::nullopt}, grid, 0.0);
  } catch (const InputError&) {
  }
  try {
    (void)studies::map_observations({"", path, std::nullopt, std::nullopt}, grid, 1.0);
  } catch (const InputError&) {
  }
  return 0;
}
