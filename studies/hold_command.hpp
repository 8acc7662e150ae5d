#pragma once
// `grainscale hold SETTINGS.yaml [--out DIR]`: a hold-scale chaff prediction (docs/hold_prediction.md).
#include <string>
#include <vector>

namespace grainscale::studies {

/// Returns the exit status; throws InputError for bad input.
int hold_command(const std::vector<std::string>& positional, const std::string& out);

}  // namespace grainscale::studies
