#include "studies/loop_study.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"
#include "studies/loop_study_report.hpp"
#include "studies/study_folder.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string existing_file(YamlMap& m, const std::string& key, const std::string& study_file) {
  const std::string path = resolve_beside(study_file, m.string(key));
  if (!fs::is_regular_file(path)) throw InputError(m.where(key) + ": cannot find the file '" + path + "'");
  return path;
}

std::string num(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

}  // namespace

LoopStudySettings load_loop_study_settings(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  LoopStudySettings s;
  s.source_file = file;
  if (root.string_or("kind", "loop") != "loop") {
    throw InputError(root.where("kind") + ": this reader takes loop studies only (study_kinds.hpp)");
  }
  s.name = root.string("name");
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos) {
    throw InputError(root.where("name") + ": a study name must be a non-empty word without '/'");
  }
  s.title = root.string_or("title", s.name);
  s.description = root.string_or("description", "");
  s.loop_file = existing_file(root, "loop", file);
  s.loop = load_loop_settings(s.loop_file);  // its InputErrors name the loop file and its keys
  if (root.has("provenance")) s.provenance = existing_file(root, "provenance", file);
  if (root.has("caveats")) {
    const YAML::Node n = YAML::LoadFile(file)["caveats"];
    if (!n.IsSequence()) throw InputError(root.where("caveats") + ": a list of sentences");
    for (const auto& c : n) {
      if (!c.IsScalar() || c.Scalar().empty()) throw InputError(root.where("caveats") + ": each entry must be a non-empty sentence");
      s.caveats.push_back(c.Scalar());
    }
    (void)root.choices_or_empty("caveats", s.caveats);  // marks the key read
  }
  if (root.has("candidates")) {
    std::vector<std::string> tried;
    for (const auto& c : s.loop.candidates) tried.push_back(c.name);
    const std::vector<std::string> keep = root.choices_or_empty("candidates", tried);
    if (keep.empty()) throw InputError(root.where("candidates") + ": the list is empty; name at least one candidate");
    const std::set<std::string> wanted(keep.begin(), keep.end());
    std::erase_if(s.loop.candidates, [&](const Candidate& c) { return !wanted.count(c.name); });
  }
  if (root.has("candidate_iterations")) {
    s.loop.candidate_iterations = static_cast<int>(root.integer("candidate_iterations", 1, 100000));
  }
  {
    YamlMap m = root.map("output");
    s.output_directory = resolve_beside(file, m.string("directory"));
    m.finish();
  }
  root.finish();
  return s;
}

LoopStudyResults run_loop_study(const LoopStudySettings& s, const StudyOptions& options, std::string& report_path) {
  const double t0 = wall_seconds_now();
  LoopStudyResults res;
  // Everything the run reads, as run: the study, loop, fit and model files, the data, the scenario.
  std::vector<std::string> inputs{s.source_file, s.loop_file, s.loop.fit.source_file, s.loop.fit.model_file};
  for (const std::string& f : {s.loop.fit.data.coverage, s.loop.fit.data.fields, s.loop.scenario_file, s.provenance}) {
    if (!f.empty() && fs::is_regular_file(f)) inputs.push_back(f);
  }
  std::set<std::string> names;
  std::vector<std::string> unique;
  for (const auto& f : inputs) {
    if (names.insert(fs::path(f).filename().string()).second) unique.push_back(f);
  }
  for (const auto& f : unique) res.inputs.push_back(fs::path(f).filename().string());
  StudyFolder folder(options.output_override.empty() ? s.output_directory : options.output_override, unique, false);
  folder.log("loop study " + s.name + " (" + s.source_file + "): grainscale loop " + s.loop_file + " with " +
             std::to_string(s.loop.candidates.size()) + " candidates");
  if (options.resume) folder.log("--resume: a loop study has no checkpoint; it runs again");
  LoopSettings loop = s.loop;
  loop.output_folder = folder.path("loop");
  res.loop = run_loop(loop);
  folder.log("loop done: base CV error " + num(res.loop.base.cv_error) + "; " +
             (res.loop.chosen >= 0 ? "added " + res.loop.candidates[res.loop.chosen].name : std::string("nothing added")) +
             "; output " + loop.output_folder);
  res.wall_seconds = wall_seconds_now() - t0;
  report_path = write_loop_study_report(s, res, folder.directory());
  folder.log("report " + report_path + " (" + num(res.wall_seconds) + " s in all)");
  return res;
}

std::string loop_study_runner(const std::string& study_file, const StudyOptions& options) {
  const LoopStudySettings s = load_loop_study_settings(study_file);
  std::string report;
  (void)run_loop_study(s, options, report);
  return report;
}

}  // namespace grainscale::studies
