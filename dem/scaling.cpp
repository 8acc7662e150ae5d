#include "dem/scaling.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dem/input_error.hpp"

namespace grainscale::dem {

const std::vector<std::string>& rolling_friction_rule_names() {
  static const std::vector<std::string> names{"keep", "inverse"};
  return names;
}

RollingFrictionRule rolling_friction_rule_from_name(const std::string& name) {
  if (name == "keep") return RollingFrictionRule::keep;
  if (name == "inverse") return RollingFrictionRule::inverse;
  throw InputError("unknown rolling-friction scaling rule '" + name + "' (allowed: keep, inverse)");
}

std::string rolling_friction_rule_name(RollingFrictionRule r) {
  return r == RollingFrictionRule::keep ? "keep" : "inverse";
}

void check_rules(const ScalingRules& rules) {
  auto check = [](double v, const char* what) {
    if (!std::isfinite(v) || v < 1) {
      std::ostringstream m;
      m << "scaling: " << what << " = " << v << " is not allowed; it must be a finite number >= 1";
      throw InputError(m.str());
    }
  };
  check(rules.factor, "factor");
  check(rules.calibrated_at, "calibrated_at");
}

Shape scale_shape(const Shape& true_size, double s) {
  Shape out = true_size;
  for (auto& c : out.spheres) c.center = s * c.center, c.radius *= s;
  for (double& d : out.measured_size) d *= s;
  return out;
}

Material scale_material(const Material& m, const ScalingRules& rules) {
  check_rules(rules);
  // Density and elastic constants are properties of the solid, not of the particle size: keeping them
  // keeps the bulk density and the ratio of contact stiffness to weight per contact area that sets
  // how a pile deforms (Bierwisch et al. 2009 keep them for their scaled particles as well).
  return m;
}

PairProperties scale_pair(const PairProperties& p, const ScalingRules& rules) {
  check_rules(rules);
  PairProperties q = p;
  // Restitution and sliding friction are dimensionless ratios of impulses and forces: unchanged.
  if (rules.rolling == RollingFrictionRule::inverse) {
    // A lever arm fixed in metres (mu_r R = const): the rolling resistance of asperities or of a contact
    // patch, whose size does not grow with the model particle.
    q.rolling_friction = p.rolling_friction * rules.calibrated_at / rules.factor;
  }
  return q;
}

MaterialTable scale_materials(const MaterialTable& t, const ScalingRules& rules) {
  check_rules(rules);
  MaterialTable out;
  for (int i = 0; i < t.size(); ++i) out.add(scale_material(t[i], rules));
  for (int a = 0; a < t.size(); ++a)
    for (int b = a; b < t.size(); ++b) {
      if (t.has_pair(a, b)) out.set_pair(a, b, scale_pair(t.pair(a, b), rules));
    }
  return out;
}

namespace {

double horizontal_width(const WallGeometry& g) {
  Vec3 lo, hi;
  g.bounds(lo, hi);
  return std::min(hi.x - lo.x, hi.y - lo.y);
}

}  // namespace

std::vector<Passage> scenario_passages(const Scenario& s) {
  std::vector<Passage> out;
  if (s.walls.empty()) return out;
  // The scenario keeps each wall's geometry but not its type; read the types back from the file that
  // load_scenario has already validated (same order as s.walls).
  YAML::Node walls;
  try {
    walls = YAML::LoadFile(s.file)["walls"];
  } catch (const YAML::Exception& e) {
    throw InputError(s.file + ": cannot read back the walls for the narrow-passage check: " + e.what());
  }
  for (std::size_t i = 0; i < s.walls.size() && i < walls.size(); ++i) {
    const YAML::Node w = walls[i];
    const std::string type = w["type"].as<std::string>();
    const WallSpec& spec = s.walls[i];
    auto radius = [&] { return w["radius"].as<double>(); };
    if (type == "pipe") {
      out.push_back({spec.name, "pipe bore", 2 * radius(), true});
    } else if (type == "tray") {
      out.push_back({spec.name, "tray", 2 * radius(), false});
    } else if (type == "cylinder_mesh" || (type == "cylinder" && (!w["inside"] || w["inside"].as<bool>()))) {
      out.push_back({spec.name, "cylinder", 2 * radius(), false});
    } else if (type == "box" || type == "box_mesh") {
      const auto lo = w["min"].as<std::vector<double>>(), hi = w["max"].as<std::vector<double>>();
      const double wx = hi[0] - lo[0], wy = hi[1] - lo[1];
      const int n = w["compartments"] ? w["compartments"].as<int>() : 1;
      if (n > 1 && wx / n < wy) out.push_back({spec.name, "box compartment", wx / n, false});
      else out.push_back({spec.name, "box", std::min(wx, wy), false});
    } else if (type == "stl") {
      out.push_back({spec.name, "STL mesh (narrowest horizontal extent of its bounding box)",
                     horizontal_width(*spec.geometry), false});
    }
    // Planes and outside-cylinders confine nothing.
  }
  return out;
}

double largest_particle_size(const Scenario& s) {
  double size = 0;
  for (const BatchSpec& b : s.particles) {
    if (b.batch.shape) size = std::max(size, b.batch.shape->sorted_dimensions().front());
    else size = std::max(size, b.batch.diameter * (1 + b.batch.diameter_spread));
  }
  return size;
}

std::vector<std::string> narrow_passage_warnings(const std::vector<Passage>& passages, double particle_size,
                                                 double scale_factor, const NarrowLimits& limits) {
  std::vector<std::string> lines;
  if (!(particle_size > 0)) return lines;
  for (const Passage& p : passages) {
    const double limit = p.opening ? limits.opening : limits.container;
    const double ratio = p.width / particle_size;
    if (ratio >= limit) continue;
    std::ostringstream m;
    m.precision(3);
    m << "wall '" << p.wall << "': the " << p.what << " is " << p.width * 1e3 << " mm wide, only " << ratio
      << " particle sizes (largest particle " << particle_size * 1e3 << " mm at scale factor " << scale_factor
      << "); below " << limit << (p.opening ? " an opening's flow" : " a container's packing")
      << " depends on the particle size, so a scaled run may differ from the true-size one (docs/scaling.md)";
    lines.push_back(m.str());
  }
  return lines;
}

std::vector<std::string> narrow_passage_warnings(const Scenario& s, const NarrowLimits& limits) {
  return narrow_passage_warnings(scenario_passages(s), largest_particle_size(s), s.settings.scale_factor, limits);
}

}  // namespace grainscale::dem
