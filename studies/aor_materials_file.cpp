#include "studies/aor_materials_file.hpp"

#include <cmath>
#include <sstream>

#include "dem/input_error.hpp"

namespace grainscale::studies {

namespace {

std::string num(double v) {
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  std::ostringstream o;
  o.precision(12);
  o << v;
  return o.str();
}

std::pair<int, int> pair_indices(const dem::MaterialTable& t, const std::string& pair, const std::string& context) {
  const auto dash = pair.find('-');
  if (dash == std::string::npos || pair.find('-', dash + 1) != std::string::npos) {
    throw InputError(context + ": pair names are 'materialA-materialB', not '" + pair + "'");
  }
  const int a = t.index(pair.substr(0, dash), context), b = t.index(pair.substr(dash + 1), context);
  if (!t.has_pair(a, b)) throw InputError(context + ": the materials file defines no pair '" + pair + "'");
  return {a, b};
}

double& field(dem::PairProperties& p, const std::string& property, const std::string& context) {
  if (property == "friction") return p.friction;
  if (property == "rolling_friction") return p.rolling_friction;
  if (property == "restitution") return p.restitution;
  throw InputError(context + ": unknown pair property '" + property + "' (friction, rolling_friction, restitution)");
}

}  // namespace

std::string materials_yaml(const dem::MaterialTable& t, const std::string& header) {
  std::ostringstream y;
  std::istringstream h(header);
  for (std::string line; std::getline(h, line);) y << "# " << line << "\n";
  y << "materials:\n";
  for (int i = 0; i < t.size(); ++i) {
    y << "  " << t[i].name << ": {density: " << num(t[i].density) << ", shear_modulus: " << num(t[i].shear_modulus)
      << ", poisson_ratio: " << num(t[i].poisson_ratio) << "}\n";
  }
  y << "pairs:\n";
  for (int a = 0; a < t.size(); ++a)
    for (int b = a; b < t.size(); ++b) {
      if (!t.has_pair(a, b)) continue;
      const dem::PairProperties& p = t.pair(a, b);
      y << "  " << t[a].name << "-" << t[b].name << ": {restitution: " << num(p.restitution)
        << ", friction: " << num(p.friction) << ", rolling_friction: " << num(p.rolling_friction) << "}\n";
    }
  return y.str();
}

void set_pair_property(dem::MaterialTable& t, const std::string& pair, const std::string& property, double value,
                       const std::string& context) {
  const auto [a, b] = pair_indices(t, pair, context);
  dem::PairProperties p = t.pair(a, b);
  field(p, property, context) = value;
  t.set_pair(a, b, p);
}

double pair_property(const dem::MaterialTable& t, const std::string& pair, const std::string& property,
                     const std::string& context) {
  const auto [a, b] = pair_indices(t, pair, context);
  dem::PairProperties p = t.pair(a, b);
  return field(p, property, context);
}

}  // namespace grainscale::studies
