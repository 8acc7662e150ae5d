#pragma once
// One run of an ensemble variant as a DEM scenario file of its own: the variant's scenario with its
// `seed` replaced (and `scale_factor`, if the variant sets one, and `time.end`, if the study sets
// one: the way to shorten or extend a long ensemble), every file it names made absolute so
// that the copy runs from the run's folder, and the output directory set. Written into the run's
// folder as scenario.yaml, it is an ordinary scenario: `grainscale dem scenario.yaml` repeats the run.
//
// The scale factor is the scenario's (docs/scaling.md): shape files are true size and scaled by it,
// densities, moduli, restitution and friction stay, the automatic time step follows the sizes. Sphere
// batches given by `diameter` are not scaled (the diameter is the run size), so a variant that changes
// the scale must use shapes; ensemble_scenario_yaml refuses one that does not.
#include <cstdint>
#include <optional>
#include <string>

namespace grainscale::studies {

/// Throws InputError naming the file when it cannot be read, or when `scale_factor` is given for a
/// scenario with sphere batches (which would not scale).
std::string ensemble_scenario_yaml(const std::string& scenario_file, std::uint64_t seed,
                                   std::optional<double> scale_factor, std::optional<double> end_time,
                                   const std::string& output_directory, const std::string& header);

}  // namespace grainscale::studies
