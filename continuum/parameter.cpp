#include "continuum/parameter.hpp"

#include <cmath>
#include <sstream>

#include "dem/input_error.hpp"

namespace grainscale::continuum {

const Parameter& ParameterSet::find(const std::string& name) const {
  for (const auto& p : params_) {
    if (p.name == name) return p;
  }
  std::string list;
  for (const auto& p : params_) list += (list.empty() ? "" : ", ") + p.name;
  throw InputError("term '" + owner_ + "' has no parameter '" + name + "'; it has: " + list);
}

bool ParameterSet::has(const std::string& name) const {
  for (const auto& p : params_) {
    if (p.name == name) return true;
  }
  return false;
}

double ParameterSet::get(const std::string& name) const { return find(name).value; }

void ParameterSet::set(const std::string& name, double value) {
  auto& p = const_cast<Parameter&>(find(name));
  if (!std::isfinite(value) || value < p.valid_lo || value > p.valid_hi) {
    std::ostringstream s;
    s << owner_ << "." << name << " = " << value << " " << p.unit << " is outside its admissible range [" << p.valid_lo
      << ", " << p.valid_hi << "]";
    throw InputError(s.str());
  }
  p.value = value;
}

}  // namespace grainscale::continuum
