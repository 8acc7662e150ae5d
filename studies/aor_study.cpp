#include "studies/aor_study.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "dem/rolling_model.hpp"
#include "dem/yaml_map.hpp"
#include "studies/aor_materials_file.hpp"

namespace grainscale::studies {

namespace {

CalibrationCase parse_case(YamlMap m, const dem::MaterialTable& materials, const std::string& materials_file) {
  CalibrationCase c;
  c.name = m.string("name");
  if (c.name.empty() || c.name.find_first_of("/\\ ") != std::string::npos) {
    throw InputError(m.where("name") + " must be a non-empty name without '/', '\\' or spaces (it names a folder)");
  }
  c.grain.material = m.string("material");
  materials.index(c.grain.material, m.where("material"));
  if (m.has("shape")) {
    c.grain.shape = resolve_beside(m.file(), m.string("shape"));
    if (m.has("diameter")) throw InputError(m.where("diameter") + ": give either 'shape' or 'diameter', not both");
  } else {
    c.grain.diameter = m.number("diameter", {0, 10, true, false});
    c.grain.diameter_spread = m.number_or("diameter_spread", 0, {0, 1, false, true});
  }
  c.grain.particle_mass = m.number_or("particle_mass", 0.0, Range::positive());
  if (m.has("count") == m.has("mass")) {
    throw InputError(m.where(m.has("count") ? "count" : "mass") + ": give exactly one of 'count' or 'mass'");
  }
  if (m.has("count")) c.count = static_cast<std::uint64_t>(m.integer("count", 10, 10'000'000));
  else c.grain.mass = m.number("mass", Range::positive());
  c.target_deg = m.number("target_deg", {0, 90, true, true});
  c.target_source = m.string_or("target_source", "measured");
  if (auto refs = m.optional_map("references")) {
    for (const std::string& k : refs->keys()) c.references.push_back({k, refs->number(k, {0, 90, true, true})});
    refs->finish();
  }
  std::set<std::string> seen;
  for (YamlMap& p : m.list_of_maps("parameters")) {
    CalibrationParameter q;
    q.pair = p.string("pair");
    q.property = p.choice("property", {"friction", "rolling_friction"});
    pair_property(materials, q.pair, q.property, p.where("pair") + " (materials " + materials_file + ")");
    const std::vector<double> r = p.numbers_or_empty("range", 2, 2, Range::closed(0, 10));
    if (r.empty()) throw InputError(p.where("range") + " is required: [low, high]");
    if (!(r[1] > r[0])) throw InputError(p.where("range") + " must be [low, high] with high > low");
    q.lo = r[0], q.hi = r[1];
    if (!seen.insert(q.label()).second) throw InputError(p.where("property") + ": '" + q.label() + "' is searched twice");
    p.finish();
    c.parameters.push_back(q);
  }
  if (c.parameters.empty()) throw InputError(m.where("parameters") + " must list at least one parameter to search");
  c.calibrated = m.numbers_or_empty("calibrated", c.parameters.size(), c.parameters.size(), Range::closed(0, 10));
  for (std::size_t k = 0; k < c.calibrated.size(); ++k) {
    if (c.calibrated[k] < c.parameters[k].lo || c.calibrated[k] > c.parameters[k].hi) {
      throw InputError(m.where("calibrated") + ": " + std::to_string(c.calibrated[k]) + " lies outside the range of '" +
                       c.parameters[k].label() + "'");
    }
  }
  m.finish();
  return c;
}

}  // namespace

CalibrationStudy load_calibration_study(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  CalibrationStudy s;
  s.file = file;
  s.name = root.string("name");
  s.materials_file = resolve_beside(file, root.string("materials"));
  const dem::MaterialTable materials = dem::MaterialTable::load(s.materials_file);
  s.scale_factor = root.number_or("scale_factor", 1.0, {1, 100, false, false});
  s.scaling.factor = s.scale_factor;
  if (auto sc = root.optional_map("scaling")) {
    s.scaling.rolling = dem::rolling_friction_rule_from_name(sc->choice_or("rolling", "keep", dem::rolling_friction_rule_names()));
    s.scaling.calibrated_at = sc->number_or("calibrated_at", 1.0, {1, 100, false, false});
    sc->finish();
  }
  if (auto c = root.optional_map("contact")) {
    s.rolling_model = c->choice_or("rolling", "constant_torque", dem::rolling_model_names());
    s.max_overlap = c->number_or("max_overlap", 0.3, {0, 1, true, false});
    c->finish();
  }
  if (auto r = root.optional_map("rig")) {
    AorRig& g = s.rig;
    g.pipe_diameter = r->number_or("pipe_diameter", g.pipe_diameter, Range::positive());
    g.pipe_length = r->number_or("pipe_length", g.pipe_length, Range::positive());
    g.tray_diameter = r->number_or("tray_diameter", g.tray_diameter, Range::positive());
    g.tray_rim_height = r->number_or("tray_rim_height", g.tray_rim_height, Range::non_negative());
    g.lift_speed = r->number_or("lift_speed", g.lift_speed, {0, 10, true, false});
    g.fill_column = r->number_or("fill_column", g.fill_column, Range::positive());
    g.floor_depth = r->number_or("floor_depth", g.floor_depth, Range::positive());
    g.wall_material = r->string_or("wall_material", g.wall_material);
    materials.index(g.wall_material, r->where("wall_material"));
    g.segments = static_cast<int>(r->integer_or("segments", g.segments, 8, 4096));
    if (!(g.tray_diameter > g.pipe_diameter)) {
      throw InputError(r->where("tray_diameter") + " must exceed the pipe's diameter (the pipe stands on the tray)");
    }
    r->finish();
  }
  if (auto t = root.optional_map("time")) {
    AorTiming& g = s.timing;
    g.step_fraction = t->number_or("step_fraction", g.step_fraction, {0, 1, true, false});
    g.pour_interval = t->number_or("pour_interval", g.pour_interval, Range::positive());
    s.pour_rate = t->number_or("pour_rate", s.pour_rate, Range::positive());
    g.settle_fill = t->number_or("settle_fill", g.settle_fill, Range::non_negative());
    g.fill_rest_speed = t->number_or("fill_rest_speed", g.fill_rest_speed, Range::positive());
    g.max_settle = t->number_or("max_settle", g.max_settle, Range::positive());
    g.rest_speed = t->number_or("rest_speed", g.rest_speed, Range::positive());
    t->finish();
  }
  if (auto q = root.optional_map("search")) {
    s.tolerance_deg = q->number_or("tolerance_deg", s.tolerance_deg, {0, 45, true, false});
    s.max_runs = static_cast<int>(q->integer_or("max_runs", s.max_runs, 1, 1000));
    if (q->has("seeds")) {
      s.seeds.clear();
      for (double v : q->numbers_or_empty("seeds", 1, 100, Range::closed(0, 9.0e15))) {
        if (v != std::floor(v)) throw InputError(q->where("seeds") + " must be whole numbers");
        s.seeds.push_back(static_cast<std::uint64_t>(v));
      }
    }
    q->finish();
  }
  std::set<std::string> names;
  for (YamlMap& c : root.list_of_maps("cases")) {
    s.cases.push_back(parse_case(c, materials, s.materials_file));
    if (!names.insert(s.cases.back().name).second) {
      throw InputError(file + ": case name '" + s.cases.back().name + "' is used twice");
    }
  }
  if (s.cases.empty()) throw InputError(root.where("cases") + " must list at least one case");
  YamlMap out = root.map("output");
  s.output_directory = out.string("directory");
  out.finish();
  root.finish();
  return s;
}

void select_cases(CalibrationStudy& study, const std::vector<std::string>& names) {
  if (names.empty()) return;
  std::string have;
  for (const CalibrationCase& c : study.cases) have += (have.empty() ? "" : ", ") + c.name;
  for (const std::string& n : names) {
    const bool known = std::any_of(study.cases.begin(), study.cases.end(), [&](const CalibrationCase& c) { return c.name == n; });
    if (!known) throw InputError("--case " + n + ": study " + study.file + " has no such case (its cases: " + have + ")");
  }
  std::vector<CalibrationCase> kept;
  for (const CalibrationCase& c : study.cases) {
    if (std::find(names.begin(), names.end(), c.name) != names.end()) kept.push_back(c);
  }
  study.cases = kept;
}

AorCase aor_case(const CalibrationStudy& study, const CalibrationCase& c, std::uint64_t seed,
                 const std::string& materials_file) {
  AorCase a;
  a.name = study.name + "_" + c.name;
  a.seed = seed;
  a.materials_file = materials_file;
  a.scale_factor = study.scale_factor;
  a.rolling_model = study.rolling_model;
  a.max_overlap = study.max_overlap;
  a.rig = study.rig;
  a.timing = study.timing;
  a.grain = c.grain;
  a.grain.pour_rate = study.pour_rate;
  if (c.count > 0) a.grain.mass = static_cast<double>(c.count) * aor_particle_mass(a);
  return a;
}

}  // namespace grainscale::studies
