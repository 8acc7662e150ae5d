#include "studies/trial_design.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dem/input_error.hpp"
#include "dem/motion/motion_from_yaml.hpp"
#include "dem/yaml_map.hpp"
#include "studies/loop_motion.hpp"

namespace grainscale::studies {

namespace {

std::string g(double v, int digits = 3) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::shared_ptr<const dem::MotionProfile> profile_of(const TrialMotion& m, const YAML::Node& block, double end_time) {
  return dem::motion_from_yaml(YamlMap(YAML::Clone(block), m.file, m.key), end_time);
}

}  // namespace

std::string TrialDesign::label() const {
  return motion + " L=" + g(length) + " m fill=" + g(fill_height * 1000) + " mm A=" + g(amplitude_deg) +
         " deg T=" + g(period) + " s";
}

YAML::Node rescaled_motion(const TrialMotion& m, bool set_amplitude, double amplitude_deg, bool set_period,
                           double period, const std::string& where) {
  YAML::Node b = YAML::Clone(m.block);
  if (!set_amplitude && !set_period) return b;
  const std::string type = b["type"] ? b["type"].as<std::string>() : "";
  if (type == "platform") {
    if (set_amplitude) b["amplitude_deg"] = amplitude_deg;
    if (set_period) {
      const double pause = b["pause"] ? b["pause"].as<double>() : 4.0;  // motion_from_yaml's default
      if (!(period > 2 * pause)) {
        throw InputError(where + ".period: " + g(period) + " s must exceed the platform's two pauses (2 x " + g(pause) +
                         " s) of motion '" + m.name + "'");
      }
      b["frequency"] = 1 / (period - 2 * pause);
    }
    return b;
  }
  if (type == "sinusoids") {
    static const char* rotations[3] = {"roll", "pitch", "yaw"};
    static const char* all[6] = {"roll", "pitch", "yaw", "surge", "sway", "heave"};
    if (set_amplitude) {
      double largest = 0;
      for (const char* r : rotations) {
        if (b[r] && b[r]["amplitude_deg"]) largest = std::max(largest, std::abs(b[r]["amplitude_deg"].as<double>()));
      }
      if (!(largest > 0)) {
        throw InputError(where + ".amplitude_deg: motion '" + m.name + "' has no rotation (roll, pitch, yaw) to set");
      }
      for (const char* r : rotations) {
        if (b[r] && b[r]["amplitude_deg"]) b[r]["amplitude_deg"] = b[r]["amplitude_deg"].as<double>() * amplitude_deg / largest;
      }
    }
    if (set_period) {
      const double own = profile_of(m, m.block, 0)->period();
      if (!(own > 0)) throw InputError(where + ".period: motion '" + m.name + "' is not periodic");
      for (const char* c : all) {
        if (b[c] && b[c]["period"]) b[c]["period"] = b[c]["period"].as<double>() * period / own;
      }
    }
    return b;
  }
  throw InputError(where + ": motion '" + m.name + "' is of type '" + type +
                   "'; only platform and sinusoids motions can have their amplitude_deg or period swept");
}

void motion_amplitude_period(const TrialMotion& m, const YAML::Node& block, double& amplitude_deg, double& period) {
  const auto p = profile_of(m, block, 0);
  period = p->period();
  if (!(period > 0)) throw InputError(m.file + ": " + m.key + ": motion '" + m.name + "' is not periodic (" + p->describe() + ")");
  amplitude_deg = cycle_facts(*p).peak_angle_deg;
}

HoldSettings hold_settings_for(const HoldSettings& base, const TrialMotion& motion, const TrialDesign& d,
                               double duration, long resolve, long average_cycles, double end_length) {
  HoldSettings s = base;
  s.name = base.name + "_" + std::to_string(d.index);
  const double dx = base.length / base.nx;
  s.length = d.length;
  s.nx = std::max(8, static_cast<int>(std::lround(d.length / dx)));
  s.fill_height = d.fill_height;
  s.depth = std::max(base.depth, d.fill_height);
  s.window = base.window >= base.fill_height ? d.fill_height : std::min(base.window, d.fill_height);
  s.direction = motion.direction;
  s.pivot_x = motion.pivot_from_centre ? 0.5 * d.length + motion.pivot_x : motion.pivot_x;
  s.pivot_z = motion.pivot_z;
  s.t_end = duration;
  const YAML::Node block = rescaled_motion(motion, d.amplitude_swept, d.amplitude_deg, d.period_swept, d.period,
                                           "sweep (design " + std::to_string(d.index) + ")");
  s.motion = profile_of(motion, block, duration);
  s.chunk = s.motion->period();
  const long total = static_cast<long>(std::ceil(duration / s.chunk - 1e-9));
  s.resolved_chunks = resolve > 0 ? std::min(resolve, total) : total;
  s.average_chunks = std::min(average_cycles, s.resolved_chunks);
  s.integrator.max_dt = base.integrator.max_dt * s.chunk / base.chunk;  // the same fraction of a cycle
  s.outputs = 1;
  s.end_zone = std::min(end_length, 0.5 * d.length);
  s.spear_depth = std::min(base.spear_depth, d.fill_height);
  s.terms.clear();
  for (const auto& [name, node] : base.terms) s.terms.emplace_back(name, YAML::Clone(node));
  return s;
}

}  // namespace grainscale::studies
