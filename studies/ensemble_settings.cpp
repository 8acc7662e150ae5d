#include "studies/ensemble_settings.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "dem/rolling_model.hpp"
#include "dem/scenario.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::studies {

namespace {

std::string existing_file(YamlMap& m, const std::string& key, const std::string& study_file) {
  const std::string path = resolve_beside(study_file, m.string(key));
  if (!std::filesystem::is_regular_file(path)) throw InputError(m.where(key) + ": cannot find the file '" + path + "'");
  return path;
}

bool is_word(const std::string& s) { return !s.empty() && s.find_first_of("/\\ \t") == std::string::npos; }

EnsembleAor parse_aor(YamlMap& a, const std::string& study_file) {
  EnsembleAor o;
  YamlMap g = a.map("grain");
  o.grain.material = g.string("material");
  o.grain.shape = existing_file(g, "shape", study_file);
  o.grain.mass = g.number("mass", Range::positive());
  o.grain.pour_rate = g.number_or("pour_rate", o.grain.pour_rate, Range::positive());
  g.finish();
  if (auto r = a.optional_map("rig")) {
    AorRig& k = o.rig;
    k.pipe_diameter = r->number_or("pipe_diameter", k.pipe_diameter, Range::positive());
    k.pipe_length = r->number_or("pipe_length", k.pipe_length, Range::positive());
    k.tray_diameter = r->number_or("tray_diameter", k.tray_diameter, Range::positive());
    k.tray_rim_height = r->number_or("tray_rim_height", k.tray_rim_height, Range::non_negative());
    k.lift_speed = r->number_or("lift_speed", k.lift_speed, {0, 10, true, false});
    k.fill_column = r->number_or("fill_column", k.fill_column, Range::positive());
    k.floor_depth = r->number_or("floor_depth", k.floor_depth, Range::positive());
    k.wall_material = r->string_or("wall_material", k.wall_material);
    if (!(k.tray_diameter > k.pipe_diameter)) {
      throw InputError(r->where("tray_diameter") + " must exceed the pipe's diameter (the pipe stands on the tray)");
    }
    r->finish();
  }
  if (auto t = a.optional_map("time")) {
    AorTiming& k = o.timing;
    k.step_fraction = t->number_or("step_fraction", k.step_fraction, {0, 1, true, false});
    k.settle_fill = t->number_or("settle_fill", k.settle_fill, Range::non_negative());
    k.fill_rest_speed = t->number_or("fill_rest_speed", k.fill_rest_speed, Range::positive());
    k.max_settle = t->number_or("max_settle", k.max_settle, Range::positive());
    k.rest_speed = t->number_or("rest_speed", k.rest_speed, Range::positive());
    t->finish();
  }
  o.rolling_model = a.choice_or("rolling", o.rolling_model, dem::rolling_model_names());
  o.max_overlap = a.number_or("max_overlap", o.max_overlap, {0, 1, true, false});
  a.finish();
  return o;
}

}  // namespace

const char* name(EnsembleQuestion q) { return q == EnsembleQuestion::congregation ? "congregation" : "scale"; }

EnsembleSettings load_ensemble_settings(const std::string& yaml_file) {
  YamlMap root = YamlMap::load_file(yaml_file);
  EnsembleSettings s;
  s.source_file = yaml_file;
  if (root.string_or("kind", "ensemble") != "ensemble") {
    throw InputError(root.where("kind") + ": this reader takes ensemble studies only (study_kinds.hpp)");
  }
  s.name = root.string("name");
  if (!is_word(s.name)) throw InputError(root.where("name") + ": a study name must be a non-empty word without '/'");
  s.title = root.string_or("title", s.name);
  s.description = root.string_or("description", "");
  s.question = root.choice_or("question", "congregation", {"congregation", "scale"}) == "scale" ? EnsembleQuestion::scale
                                                                                               : EnsembleQuestion::congregation;

  std::set<std::string> names;
  for (YamlMap& v : root.list_of_maps("variants")) {
    EnsembleVariant e;
    e.name = v.string("name");
    if (!is_word(e.name)) throw InputError(v.where("name") + ": a variant name must be a non-empty word (it names a folder)");
    if (!names.insert(e.name).second) throw InputError(v.where("name") + ": variant '" + e.name + "' is named twice");
    e.label = v.string_or("label", e.name);
    e.scenario = existing_file(v, "scenario", yaml_file);
    if (v.has("scale_factor")) e.scale_factor = v.number("scale_factor", {1, 100, false, false});
    v.finish();
    // The scenario must load alone (a typo costs nothing yet).
    try {
      dem::load_scenario(e.scenario);
    } catch (const InputError& err) {
      throw InputError(v.where("scenario") + ": " + err.what());
    }
    s.variants.push_back(e);
  }
  if (s.variants.size() < 2) throw InputError(root.where("variants") + ": list at least two variants to compare");

  const std::vector<double> seeds = root.numbers_or_empty("seeds", 0, 1000, Range::closed(0, 9.0e15));
  if (seeds.empty()) throw InputError(root.where("seeds") + ": list at least one seed, e.g. [1, 2, 3]");
  std::set<std::uint64_t> seen;
  for (double v : seeds) {
    if (v != std::floor(v)) throw InputError(root.where("seeds") + ": seeds must be whole numbers");
    if (!seen.insert(static_cast<std::uint64_t>(v)).second) throw InputError(root.where("seeds") + ": seed " + std::to_string(static_cast<std::uint64_t>(v)) + " is listed twice");
    s.seeds.push_back(static_cast<std::uint64_t>(v));
  }

  if (root.has("end_time")) {
    s.end_time = root.number("end_time", Range::positive());
  }
  if (auto c = root.optional_map("compare")) {
    s.reference = c->string_or("reference", s.variants.front().name);
    if (!names.count(s.reference)) throw InputError(c->where("reference") + ": no variant is named '" + s.reference + "'");
    s.confidence = c->number_or("confidence", s.confidence, {0.5, 1, false, true});
    c->finish();
  } else {
    s.reference = s.variants.front().name;
  }

  {
    YamlMap m = root.map("cg");
    s.cg_settings = existing_file(m, "settings", yaml_file);
    s.motion_from = m.number_or("motion_from", 0.0, Range::non_negative());
    m.finish();
    YAML::Node cg;
    try {
      cg = YAML::LoadFile(s.cg_settings);
    } catch (const YAML::Exception& e) {
      throw InputError(s.cg_settings + ": " + e.what());
    }
    if (!cg["grid"] || !cg["grid"]["dimension"] || cg["grid"]["dimension"].as<std::string>() != "2") {
      throw InputError(s.cg_settings + ": key 'grid.dimension' must be 2 for an ensemble study (bulk density and "
                       "surface flow are read from an (x, z) grid)");
    }
  }
  if (s.end_time && *s.end_time <= s.motion_from) {
    throw InputError(root.where("end_time") + ": must be later than cg.motion_from (" + std::to_string(s.motion_from) +
                     " s): the runs would end before the motion starts");
  }
  if (auto a = root.optional_map("aor")) s.aor = parse_aor(*a, yaml_file);
  {
    YamlMap m = root.map("output");
    s.output_directory = resolve_beside(yaml_file, m.string("directory"));
    m.finish();
  }
  root.finish();
  return s;
}

}  // namespace grainscale::studies
