#include "studies/option_number.hpp"

#include "dem/input_error.hpp"

namespace grainscale::studies {

long whole_number_option(const std::string& option, const std::string& value) {
  std::size_t used = 0;
  long n = 0;
  try {
    n = std::stol(value, &used);
  } catch (...) {
    used = 0;
  }
  if (used == 0 || used != value.size()) throw InputError(option + ": '" + value + "' is not a whole number");
  return n;
}

double number_option(const std::string& option, const std::string& value) {
  std::size_t used = 0;
  double d = 0;
  try {
    d = std::stod(value, &used);
  } catch (...) {
    used = 0;
  }
  if (used == 0 || used != value.size()) throw InputError(option + ": '" + value + "' is not a number");
  return d;
}

int thread_count_option(const std::string& value) {
  const long n = whole_number_option("--threads", value);
  if (n < 1 || n > 1024) throw InputError("--threads: counts must be in [1, 1024]");
  return static_cast<int>(n);
}

}  // namespace grainscale::studies
