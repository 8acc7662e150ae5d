#include "studies/study_settings.hpp"

#include <filesystem>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"
#include "continuum/settings.hpp"
#include "studies/fit_command.hpp"

namespace grainscale::studies {

namespace {


std::string existing_file(YamlMap& m, const std::string& key, const std::string& study_file) {
  const std::string path = resolve_beside(study_file, m.string(key));
  if (!std::filesystem::is_regular_file(path)) throw InputError(m.where(key) + ": cannot find the file '" + path + "'");
  return path;
}

}  // namespace

StudySettings load_study_settings(const std::string& yaml_file) {
  YamlMap root = YamlMap::load_file(yaml_file);
  StudySettings s;
  s.source_file = yaml_file;
  s.name = root.string("name");
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos) {
    throw InputError(root.where("name") + ": a study name must be a non-empty word without '/'");
  }
  if (root.string_or("kind", "platform") != "platform") {
    throw InputError(root.where("kind") + ": this reader takes platform studies only (study_kinds.hpp)");
  }
  s.title = root.string_or("title", s.name);
  s.description = root.string_or("description", "");

  {
    YamlMap m = root.map("dem");
    s.scenario = existing_file(m, "scenario", yaml_file);
    m.finish();
  }
  {
    YamlMap m = root.map("cg");
    s.cg_settings = existing_file(m, "settings", yaml_file);
    s.flow_from = m.number_or("flow_from", 0.0, Range::non_negative());
    s.flow_to = m.number_or("flow_to", 1e300, Range::non_negative());
    if (s.flow_to <= s.flow_from) throw InputError(m.where("flow_to") + ": must be later than flow_from");
    m.finish();
  }
  {
    YamlMap m = root.map("fit");
    s.model = existing_file(m, "model", yaml_file);
    // The model file must load on its own (the study replaces its flow, initial state and output).
    s.fit_parameters = m.choices_or_empty("parameters", fittable_parameters(continuum::load_continuum_settings(s.model)));
    if (s.fit_parameters.empty()) throw InputError(m.where("parameters") + ": name at least one parameter to fit");
    YamlMap d = m.map("data");
    s.fit_fields = d.boolean_or("fields", true);
    s.fit_coverage = d.boolean_or("coverage", true);
    if (!s.fit_fields && !s.fit_coverage) throw InputError(d.where("fields") + ": fit to fields, coverage or both");
    s.field_sigma = d.number_or("field_sigma", 0.02, Range::positive());
    s.coverage_sigma = d.number_or("coverage_sigma", 0.05, Range::positive());
    s.data_from = d.number_or("from", 0.0, Range::non_negative());
    s.data_every = static_cast<int>(d.integer_or("every", 1, 1, 100000));
    s.min_solid_fraction = d.number_or("min_solid_fraction", 0.3, Range::closed(0, 1));
    d.finish();
    s.max_iterations = static_cast<int>(m.integer_or("max_iterations", 30, 1, 100000));
    m.finish();
  }
  {
    YamlMap m = root.map("predict");
    s.predict_end = m.number("end", Range::positive());
    s.predict_outputs = static_cast<int>(m.integer_or("outputs", 12, 1, 100000));
    m.finish();
  }
  if (auto m = root.optional_map("compare")) {
    s.end_length = m->number_or("end_length", 0.1, Range::positive());
    m->finish();
  }
  {
    YamlMap m = root.map("output");
    s.output_directory = resolve_beside(yaml_file, m.string("directory"));
    m.finish();
  }
  root.finish();
  return s;
}

}  // namespace grainscale::studies
