#include "studies/option_number.hpp"

#include <cstddef>

#include "dem/input_error.hpp"

namespace grainscale::studies {

namespace {
/// `parse(value, &used)` (a std::sto* function) must use all of `value`, else an InputError saying
/// that `value` is not `what`.
template <class Parse>
auto all_of(const std::string& option, const std::string& value, const char* what, Parse parse) {
  std::size_t used = 0;
  decltype(parse(value, &used)) x{};
  try {
    x = parse(value, &used);
  } catch (...) {
    used = 0;
  }
  if (used == 0 || used != value.size()) throw InputError(option + ": '" + value + "' is not " + what);
  return x;
}
}  // namespace

long whole_number_option(const std::string& option, const std::string& value) {
  return all_of(option, value, "a whole number", [](const std::string& v, std::size_t* used) { return std::stol(v, used); });
}

double number_option(const std::string& option, const std::string& value) {
  return all_of(option, value, "a number", [](const std::string& v, std::size_t* used) { return std::stod(v, used); });
}

int thread_count_option(const std::string& value) {
  const long n = whole_number_option("--threads", value);
  if (n < 1 || n > 1024) throw InputError("--threads: counts must be in [1, 1024]");
  return static_cast<int>(n);
}

}  // namespace grainscale::studies
