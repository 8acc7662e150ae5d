#pragma once
// A named model coefficient with its unit and prior range (docs/continuum.md lists the sources).
// Fits address coefficients as "term.name", e.g. "segregation.S".
#include <string>
#include <vector>

namespace grainscale::continuum {

struct Parameter {
  std::string name;     // e.g. "S"
  std::string unit;     // e.g. "m"
  double value = 0;
  double valid_lo = 0;  // physically admissible range: values outside are input errors
  double valid_hi = 0;
  double prior_lo = 0;  // plausible range for granular beds (docs/continuum.md); fits start inside it
  double prior_hi = 0;
  std::string meaning;  // one line for reports
  bool optional = false; // may be left out of the YAML (keeps `value`)
};

/// The parameters of one flux term. set() checks the name and the admissible range.
class ParameterSet {
 public:
  ParameterSet(std::string owner, std::vector<Parameter> params) : owner_(std::move(owner)), params_(std::move(params)) {}
  const std::vector<Parameter>& all() const { return params_; }
  double get(const std::string& name) const;
  void set(const std::string& name, double value);
  bool has(const std::string& name) const;

 private:
  const Parameter& find(const std::string& name) const;
  std::string owner_;
  std::vector<Parameter> params_;
};

}  // namespace grainscale::continuum
