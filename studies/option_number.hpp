#pragma once
// Numbers given on the command line (`--steps 500`, `--threads 1,2`, `--density 1250`). The whole
// value must be the number: "10x" is an input error naming the option and the value, not 10 (what
// std::stol alone makes of it).
#include <string>

namespace grainscale::studies {

/// A whole number; throws InputError "OPTION: 'VALUE' is not a whole number".
long whole_number_option(const std::string& option, const std::string& value);
/// A finite or infinite decimal number; throws InputError "OPTION: 'VALUE' is not a number".
double number_option(const std::string& option, const std::string& value);
/// One thread count of `--threads`, in [1, 1024]; throws InputError naming the value or the range.
int thread_count_option(const std::string& value);

}  // namespace grainscale::studies
