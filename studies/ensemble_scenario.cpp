#include "studies/ensemble_scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::studies {

namespace {

void make_absolute(YAML::Node node, const std::string& key, const std::string& file) {
  if (node && node.IsMap() && node[key] && node[key].IsScalar()) {
    node[key] = std::filesystem::absolute(resolve_beside(file, node[key].as<std::string>())).lexically_normal().string();
  }
}

}  // namespace

std::string ensemble_scenario_yaml(const std::string& scenario_file, std::uint64_t seed,
                                   std::optional<double> scale_factor, std::optional<double> end_time,
                                   const std::string& output_directory, const std::string& header) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(scenario_file);
  } catch (const YAML::Exception& e) {
    throw InputError(scenario_file + ": " + e.what());
  }
  if (!root.IsMap()) throw InputError(scenario_file + ": a scenario must be a mapping");
  root["seed"] = seed;
  if (scale_factor) {
    for (const auto& p : root["particles"]) {
      if (p.IsMap() && !p["shape"]) {
        throw InputError(scenario_file + ": key 'particles': a variant with its own scale_factor needs shape batches; "
                         "a sphere batch's diameter is its run size and would not scale (docs/scaling.md)");
      }
    }
    root["scale_factor"] = *scale_factor;
  }
  if (end_time) {
    if (!root["time"] || !root["time"].IsMap()) root["time"] = YAML::Node(YAML::NodeType::Map);
    root["time"]["end"] = *end_time;
  }
  make_absolute(root, "materials", scenario_file);
  for (auto w : root["walls"]) {
    make_absolute(w, "file", scenario_file);
    make_absolute(w["motion"], "file", scenario_file);
  }
  for (auto p : root["particles"]) make_absolute(p, "shape", scenario_file);
  if (!root["output"] || !root["output"].IsMap()) root["output"] = YAML::Node(YAML::NodeType::Map);
  root["output"]["directory"] = output_directory;
  YAML::Emitter e;
  e << root;
  if (!e.good()) throw InputError(scenario_file + ": cannot write it back: " + e.GetLastError());
  return header + e.c_str() + "\n";
}

}  // namespace grainscale::studies
