#pragma once
// The one place where flux terms are registered by name (the YAML key under `terms:`).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "continuum/flux_term.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::continuum {

struct TermEntry {
  std::string name;
  std::string summary;
  std::function<std::unique_ptr<FluxTerm>(YamlMap&)> make;  // reads its keys from the term's mapping
  /// A candidate effect for `grainscale loop` (docs/loop.md): the parameters it fits, starting at the
  /// geometric mean of their prior range. Empty: part of the base model, not a candidate.
  std::vector<std::string> candidate_parameters = {};
};

const std::vector<TermEntry>& term_registry();
std::vector<std::string> term_names();
/// Build the term `name` from its YAML mapping; throws InputError for unknown names, keys or ranges.
std::unique_ptr<FluxTerm> make_term(const std::string& name, YamlMap& params);

}  // namespace grainscale::continuum
