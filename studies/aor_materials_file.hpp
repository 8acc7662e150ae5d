#pragma once
// A materials table written back as a materials file (the format MaterialTable::load reads,
// docs/scenario.md), for the runs of a calibration and for its calibrated result.
#include <string>

#include "dem/material.hpp"

namespace grainscale::studies {

/// The file's text: `header` (each line prefixed with "# "), then every material and every defined
/// pair. Numbers keep 12 significant digits; a rigid material's shear modulus is written as .inf.
std::string materials_yaml(const dem::MaterialTable& table, const std::string& header);

/// Set one pair property ("friction", "rolling_friction" or "restitution") of the pair "a-b".
/// Throws InputError naming `context` if the pair or property is unknown.
void set_pair_property(dem::MaterialTable& table, const std::string& pair, const std::string& property, double value,
                       const std::string& context);
/// Read one pair property (same names).
double pair_property(const dem::MaterialTable& table, const std::string& pair, const std::string& property,
                     const std::string& context);

}  // namespace grainscale::studies
