#include "studies/hold_study_settings.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string existing_file(YamlMap& m, const std::string& key, const std::string& study_file) {
  const std::string path = resolve_beside(study_file, m.string(key));
  if (!fs::is_regular_file(path)) throw InputError(m.where(key) + ": cannot find the file '" + path + "'");
  return path;
}

}  // namespace

void shorten_hold(HoldSettings& s, double end) {
  const long old_total = static_cast<long>(std::ceil(s.t_end / s.chunk - 1e-9));
  s.t_end = end;
  const long total = static_cast<long>(std::ceil(s.t_end / s.chunk - 1e-9));
  // "all" stays all; a count of resolved cycles is capped at the new total (then all are resolved,
  // and no averaging window is needed); below it, average_chunks <= resolved_chunks still holds.
  s.resolved_chunks = s.resolved_chunks >= old_total ? total : std::min(s.resolved_chunks, total);
}

HoldStudySettings load_hold_study_settings(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  HoldStudySettings s;
  s.source_file = file;
  if (root.string_or("kind", "hold") != "hold") {
    throw InputError(root.where("kind") + ": this reader takes hold studies only (study_kinds.hpp)");
  }
  s.name = root.string("name");
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos) {
    throw InputError(root.where("name") + ": a study name must be a non-empty word without '/'");
  }
  s.title = root.string_or("title", s.name);
  s.description = root.string_or("description", "");
  std::vector<YamlMap> list = root.list_of_maps("scenarios");
  if (list.empty()) throw InputError(root.where("scenarios") + ": the list is empty; name at least one hold settings file");
  for (YamlMap& m : list) {
    HoldStudyScenario sc;
    sc.file = existing_file(m, "file", file);
    sc.settings = load_hold_settings(sc.file);  // InputErrors name the scenario file itself
    sc.file_end = sc.settings.t_end;
    if (m.has("end")) {
      const double end = m.number("end", Range{0, sc.file_end, true, false});
      sc.shortened = end < sc.file_end;
      shorten_hold(sc.settings, end);
    }
    sc.compare_with_report = m.boolean_or("compare_with_report", false);
    m.finish();
    for (const HoldStudyScenario& other : s.scenarios) {
      if (other.settings.name == sc.settings.name) {
        throw InputError(m.where("file") + ": scenario name '" + sc.settings.name + "' (from " + sc.file +
                         ") is already used by " + other.file + "; each scenario writes the subfolder of its name");
      }
    }
    if (sc.settings.name.empty() || sc.settings.name.find_first_of("/\\") != std::string::npos ||
        sc.settings.name == "inputs") {
      throw InputError(m.where("file") + ": the scenario's name '" + sc.settings.name +
                       "' must be a word without '/' other than 'inputs' (it names a subfolder)");
    }
    s.scenarios.push_back(std::move(sc));
  }
  if (auto v = root.optional_map("validate")) {
    HoldStudyValidation val;
    val.cg_fields = existing_file(*v, "cg_fields", file);
    val.dem_scenario = existing_file(*v, "dem_scenario", file);
    val.container = v->string_or("container", "");
    val.material_from = v->string("material_from");
    const bool listed = std::any_of(s.scenarios.begin(), s.scenarios.end(),
                                    [&](const HoldStudyScenario& sc) { return sc.settings.name == val.material_from; });
    if (!listed) {
      std::string names;
      for (const auto& sc : s.scenarios) names += (names.empty() ? "" : ", ") + sc.settings.name;
      throw InputError(v->where("material_from") + ": '" + val.material_from + "' is not a listed scenario (" + names + ")");
    }
    if (v->has("measure_depth")) val.measure_depth = v->number("measure_depth", Range{0, 1, true, false});
    if (auto f = v->optional_map("fit")) {
      ClosureFitSettings fs;
      fs.train_until = f->number("train_until", Range::positive());
      fs.parameters = f->choices_or_empty(
          "parameters", {"internal_friction_deg", "basal_friction_deg", "flowing_layer_diameters", "delta_mu", "start_excess_deg"});
      f->finish();
      val.fit = fs;
    }
    v->finish();
    s.validate = val;
  }
  {
    YamlMap m = root.map("output");
    s.output_directory = resolve_beside(file, m.string("directory"));
    m.finish();
  }
  root.finish();
  return s;
}

}  // namespace grainscale::studies
