#pragma once
// Registry of rolling-resistance models. Adding one: a header in dem/contact/ with the evaluator,
// an enumerator here, and one line in rolling_model_names / ForceField::make_models().
#include <string>
#include <vector>

namespace grainscale::dem {

enum class RollingModel { none, constant_torque, epsd };

inline const std::vector<std::string>& rolling_model_names() {
  static const std::vector<std::string> names{"none", "constant_torque", "epsd"};
  return names;
}

inline RollingModel rolling_model_from_name(const std::string& s) {
  if (s == "none") return RollingModel::none;
  if (s == "epsd") return RollingModel::epsd;
  return RollingModel::constant_torque;
}

struct RollingSettings {
  RollingModel model = RollingModel::constant_torque;
  double epsd_stiffness_factor = 2.25;  // Ai et al. (2011) eq. 15
  double epsd_damping_ratio = 0.3;      // Ai et al. (2011) eta_r
};

}  // namespace grainscale::dem
