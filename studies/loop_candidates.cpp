#include "studies/loop_candidates.hpp"

#include <cmath>

#include "continuum/term_registry.hpp"
#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::studies {

std::vector<Candidate> candidate_library() {
  std::vector<Candidate> out;
  for (const auto& e : continuum::term_registry()) {
    if (e.candidate_parameters.empty()) continue;
    Candidate c{e.name, e.summary, true, {}, YAML::Node(YAML::NodeType::Map)};
    for (const auto& p : e.candidate_parameters) c.fitted.push_back(e.name + "." + p);
    out.push_back(c);
  }
  out.push_back({"observation_depth",
                 "mis-specified observation operator: the visible top layer delta of coverage = 1 - exp(-kappa int c dz) is fitted",
                 false, {"observation.delta"}, YAML::Node(YAML::NodeType::Map)});
  return out;
}

std::vector<std::string> candidate_names() {
  std::vector<std::string> names;
  for (const auto& c : candidate_library()) names.push_back(c.name);
  return names;
}

YAML::Node term_node(const Candidate& c) {
  YAML::Node node = YAML::Clone(c.settings);
  for (const auto& q : c.fitted) {
    const std::string p = q.substr(q.find('.') + 1);
    if (!node[p]) node[p] = 0.0;
  }
  return node;
}

void add_candidate(const Candidate& c, continuum::Model& model, const MotionFacts* motion, const std::string& source) {
  if (!c.term) return;
  YAML::Node node = term_node(c);  // placeholders: set to their starting values below
  if (motion) {
    const std::pair<const char*, double> facts[] = {{"omega2", motion->omega2_mean},
                                                    {"alpha2", motion->alpha2_mean},
                                                    {"axis_x", motion->axis_x},
                                                    {"axis_z", motion->axis_z},
                                                    {"pause_fraction", motion->pause_fraction}};
    // Only keys the term has: build it once to learn its parameter names.
    YamlMap probe(YAML::Clone(node), source, "candidates." + c.name);
    const auto term = continuum::make_term(c.name, probe);
    for (const auto& [key, value] : facts) {
      if (term->parameters().has(key) && !node[key]) node[key] = value;
    }
  }
  YamlMap m(node, source, "candidates." + c.name);
  auto term = continuum::make_term(c.name, m);
  for (const auto& q : c.fitted) {
    const std::string p = q.substr(q.find('.') + 1);
    if (c.settings[p]) continue;  // the user's start
    for (const auto& par : term->parameters().all()) {
      if (par.name == p) term->parameters().set(p, std::sqrt(par.prior_lo * par.prior_hi));
    }
  }
  model.add_term(std::move(term));
}

}  // namespace grainscale::studies
