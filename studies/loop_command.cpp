#include "studies/loop_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "continuum/settings.hpp"
#include "continuum/term_registry.hpp"
#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"
#include "grainscale_version.hpp"
#include "studies/fit_plots.hpp"
#include "studies/loop_cg_fields.hpp"
#include "studies/loop_report.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

LoopSettings load_loop_settings(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  LoopSettings s;
  s.source_file = file;
  {
    const std::string fit_file = resolve_beside(file, root.string("fit"));
    if (!fs::exists(fit_file)) throw InputError(root.where("fit") + ": cannot find '" + fit_file + "' (a grainscale fit settings file)");
    s.fit = load_fit_command_settings(fit_file);
  }
  if (root.has("scenario")) {
    s.scenario_file = resolve_beside(file, root.string("scenario"));
    if (!fs::exists(s.scenario_file)) throw InputError(root.where("scenario") + ": cannot find '" + s.scenario_file + "'");
    s.container = root.string_or("container", "");
    s.motion = motion_facts(s.scenario_file, s.container);
  } else if (root.has("container")) {
    throw InputError(root.where("container") + ": 'container' names a wall of the scenario; give 'scenario' too");
  }
  const std::vector<Candidate> library = candidate_library();
  auto find = [&](const std::string& name) {
    for (const auto& c : library)
      if (c.name == name) return c;
    throw InputError("unreachable");
  };
  const YAML::Node raw = YAML::LoadFile(file)["candidates"];
  if (!raw) {
    s.candidates = library;
  } else if (raw.IsMap()) {
    YamlMap m = root.map("candidates");
    for (const std::string& name : m.keys()) {
      const auto names = candidate_names();
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw InputError(m.where(name) + ": unknown candidate '" + name + "'; choose from: " + list);
      }
      YamlMap entry = m.map(name);
      Candidate c = find(name);
      c.settings = YAML::Clone(raw[name]);
      if (c.term && c.settings["fit"]) {
        // `fit: [S, layer]`: which of the term's parameters the loop fits (default: the registry's).
        c.settings.remove("fit");
        YamlMap probe(term_node(c), file, "candidates." + name);
        const auto term = continuum::make_term(name, probe);
        std::vector<std::string> params;
        for (const auto& p : term->parameters().all()) params.push_back(p.name);
        const std::vector<std::string> chosen = entry.choices_or_empty("fit", params);
        if (chosen.empty()) throw InputError(entry.where("fit") + ": name at least one parameter to fit");
        c.fitted.clear();
        for (const std::string& p : chosen) c.fitted.push_back(name + "." + p);
      }
      s.candidates.push_back(c);
    }
  } else {
    for (const std::string& name : root.choices_or_empty("candidates", candidate_names())) s.candidates.push_back(find(name));
  }
  if (s.candidates.empty()) throw InputError(root.where("candidates") + ": no candidates to try");
  for (const auto& c : s.candidates) {
    if (!c.term && s.fit.data.coverage.empty()) {
      throw InputError(root.where("candidates") + ": " + c.name + " changes the coverage operator; it needs coverage data");
    }
    // Build it once so a bad key or value is reported now, naming the settings file.
    continuum::Model trial = continuum::build_model(s.fit.model);
    if (c.term && trial.has_term(c.name)) {
      throw InputError(root.where("candidates") + ": the model already has the term " + c.name + "; it cannot be a candidate");
    }
    add_candidate(c, trial, s.motion ? &*s.motion : nullptr, file);
  }
  if (auto m = root.optional_map("cv")) {
    s.cv.by = m->choice_or("by", "auto", {"auto", "time", "x"});
    s.cv.blocks = static_cast<int>(m->integer_or("blocks", 4, 2, 100));
    m->finish();
  }
  if (auto m = root.optional_map("selection")) {
    s.min_cv_gain = m->number_or("min_cv_gain", 0.02, Range::closed(0, 1));
    s.bic_drop = m->number_or("bic_drop", 10, Range::non_negative());
    m->finish();
  }
  s.diagnosis.period = s.motion ? s.motion->period : 0;
  if (auto m = root.optional_map("diagnosis")) {
    s.diagnosis.period = m->number_or("period", s.diagnosis.period, Range::non_negative());
    s.diagnosis.surface_layer = m->number_or("surface_layer", 0.0, Range::non_negative());
    s.diagnosis.wall_band = m->number_or("wall_band", 0.0, Range::non_negative());
    s.diagnosis.max_lag = static_cast<int>(m->integer_or("max_lag", 8, 1, 1000));
    s.diagnosis.alpha = m->number_or("alpha", 0.01, {0, 1, true, true});
    m->finish();
  }
  if (s.diagnosis.surface_layer == 0) s.diagnosis.surface_layer = s.fit.model.delta;
  s.candidate_iterations = static_cast<int>(root.integer_or("candidate_iterations", 40, 1, 100000));
  s.output_folder = resolve_beside(file, root.string("output"));
  root.finish();
  return s;
}

LoopResult run_loop(const LoopSettings& s) {
  LoopResult res;
  fs::create_directories(s.output_folder);
  FitCommandSettings fit = s.fit;
  if (fit.data.fields.size() > 3 && fit.data.fields.substr(fit.data.fields.size() - 3) == ".h5") {
    const std::string csv = (fs::path(s.output_folder) / "fields_from_h5.csv").string();
    cg_fields_to_csv(fit.data.fields, csv);
    fit.data.fields = csv;
    res.files.push_back(csv);
  }
  auto base_model = [&]() {
    continuum::Model m = continuum::build_model(fit.model);
    for (const auto& [name, v] : fit.start)
      if (name.rfind("observation.", 0) != 0) m.set_parameter(name, v);
    return m;
  };
  auto base_observation = [&]() {
    continuum::SurfaceCoverage o(fit.model.kappa, fit.model.delta);
    for (const auto& [name, v] : fit.start)
      if (name.rfind("observation.", 0) == 0) o.parameters().set(name.substr(12), v);
    return o;
  };
  const continuum::Model probe = base_model();
  res.data = map_observations(fit.data, probe.grid(), fit.t0);
  Problem pr;
  pr.start = {continuum::initial_field(fit.model, probe.grid()), fit.t0, fit.model.stops};
  pr.data = &res.data;
  pr.fit = fit.fit;
  pr.cv = s.cv;

  // (1) The base model.
  res.base = evaluate("base", {base_model, base_observation}, fit.fit.parameters, pr);
  if (!res.base.ok) throw InputError("loop: the base fit failed: " + res.base.error);
  const MotionFacts* motion = s.motion ? &*s.motion : nullptr;
  // (2) Diagnosis of its residual.
  res.diagnosis_before = diagnose(probe.grid(), residual_points(probe.grid(), res.data, res.base.prediction), s.diagnosis);

  // (3) Each candidate on top of the base, starting from the base optimum.
  // A base parameter the data drove to zero starts the candidates' fits at kRanToZero.
  std::vector<std::pair<std::string, double>> base_values;
  for (std::size_t j = 0; j < res.base.parameters.size(); ++j)
    base_values.push_back({res.base.parameters[j], std::max(res.base.values[j], kRanToZero)});
  Problem cp = pr;
  cp.fit.max_iterations = s.candidate_iterations;
  for (const Candidate& c : s.candidates) {
    auto model = [&, c]() {
      continuum::Model m = base_model();
      for (const auto& [name, v] : base_values)
        if (name.rfind("observation.", 0) != 0) m.set_parameter(name, v);
      add_candidate(c, m, motion, s.source_file);
      return m;
    };
    auto observation = [&]() {
      continuum::SurfaceCoverage o = base_observation();
      for (const auto& [name, v] : base_values)
        if (name.rfind("observation.", 0) == 0) o.parameters().set(name.substr(12), v);
      return o;
    };
    std::vector<std::string> params = fit.fit.parameters;
    for (const auto& p : c.fitted)
      if (std::find(params.begin(), params.end(), p) == params.end()) params.push_back(p);
    if (params.size() == fit.fit.parameters.size()) {
      Evaluation e;
      e.name = c.name;
      e.error = "its parameters are already fitted in the base model";
      res.candidates.push_back(e);
      continue;
    }
    std::cout << "loop: candidate " << c.name << " ..." << std::flush;
    res.candidates.push_back(evaluate(c.name, {model, observation}, params, cp));
    Evaluation& e = res.candidates.back();
    if (!c.term) {
      // Coverage sees the top delta through the cells it overlaps: while the top cell is thicker
      // than delta, coverage depends on kappa * delta only, and the fit cannot tell them apart.
      const continuum::Grid& g = probe.grid();
      double top = INFINITY;
      for (int i = 0; i < g.nx(); ++i) top = std::min(top, g.dsigma() * g.h_column(i));
      const double delta = base_observation().parameters().get("delta");
      if (top >= delta) {
        e.warnings.push_back("the top cell (" + std::to_string(1e3 * top) + " mm) is not thinner than the assumed delta (" +
                             std::to_string(1e3 * delta) +
                             " mm): coverage depends on kappa * delta only there; use a grid with cells thinner than delta");
      }
    }
    std::printf(" %s (%.1f s)\n", e.ok ? ("CV error " + std::to_string(e.cv_error)).c_str() : e.error.c_str(), e.seconds);
  }
  std::stable_sort(res.candidates.begin(), res.candidates.end(), [](const Evaluation& a, const Evaluation& b) {
    const double ea = a.ok && std::isfinite(a.cv_error) ? a.cv_error : INFINITY;
    const double eb = b.ok && std::isfinite(b.cv_error) ? b.cv_error : INFINITY;
    return ea < eb;
  });

  // (4) The winner, if justified.
  std::ostringstream why;
  if (!std::isfinite(res.base.cv_error)) {
    why << "no cross-validated error for the base model (" << res.base.cv_folds
        << " usable folds): the data are too few to justify any added effect";
  } else {
    for (std::size_t j = 0; j < res.candidates.size(); ++j) {
      const Evaluation& e = res.candidates[j];
      if (!e.ok || !std::isfinite(e.cv_error)) continue;
      // Relative drop of the held-out chi2 (mean r²): what the candidate predicts better.
      const double gain = 1 - (e.cv_error * e.cv_error) / (res.base.cv_error * res.base.cv_error), dbic = e.bic - res.base.bic;
      bool constrained = true;
      for (std::size_t p = fit.fit.parameters.size(); p < e.parameters.size(); ++p)
        constrained = constrained && e.standard_errors[p] < e.values[p] && e.values[p] > 0 && !e.at_bound[p];
      if (gain >= s.min_cv_gain && dbic <= -s.bic_drop && constrained) {
        res.chosen = static_cast<int>(j);
        why << e.name << " has the lowest cross-validated error that is justified: CV error " << e.cv_error << " vs "
             << res.base.cv_error << " for the base (held-out chi2 " << 100 * gain << " % lower, at least " << 100 * s.min_cv_gain
            << " % needed), BIC lower by " << -dbic << " (at least " << s.bic_drop << " needed), strength constrained";
        break;
      }
      if (j == 0) {
        why << "the best candidate by CV error, " << e.name << ", is not justified (held-out chi2 " << 100 * gain
            << " % lower, needs " << 100 * s.min_cv_gain << " %; BIC change " << dbic << ", needs <= " << -s.bic_drop
            << (constrained ? "" : "; its strength is not constrained (standard error not below it, or at a bound)") << ")";
      }
    }
    if (res.chosen < 0) {
      const bool any = std::any_of(res.candidates.begin(), res.candidates.end(),
                                   [](const Evaluation& e) { return e.ok && std::isfinite(e.cv_error); });
      const bool fitted = std::any_of(res.candidates.begin(), res.candidates.end(), [](const Evaluation& e) { return e.ok; });
      if (!fitted) why << "no candidate could be fitted (see each one's error)";
      else if (!any) why << "no candidate could be cross-validated (every fold leaves too few observations for its parameters)";
      why << "; no candidate meets the criteria, so none is added";
    }
  }
  res.reason = why.str();
  const Evaluation& after = res.chosen >= 0 ? res.candidates[res.chosen] : res.base;
  res.diagnosis_after = diagnose(probe.grid(), residual_points(probe.grid(), res.data, after.prediction), s.diagnosis);
  const auto written = write_loop_outputs(s, fit, probe.grid(), res);
  res.files.insert(res.files.end(), written.begin(), written.end());
  return res;
}

int loop_command(const std::vector<std::string>& positional, const std::string& out) {
  if (positional.size() != 1) throw InputError("usage: grainscale loop SETTINGS.yaml [--out DIR]");
  LoopSettings s = load_loop_settings(positional[0]);
  if (!out.empty()) s.output_folder = out;
  const LoopResult r = run_loop(s);
  std::printf("base: chi2/dof = %.4g, CV error %.4g (%s blocks); residual %s\n", r.base.chi2 / std::max(1, r.base.n - r.base.k),
              r.base.cv_error, r.base.cv_by.c_str(),
              !r.diagnosis_before.tested ? "untested (too few points)" : r.diagnosis_before.white ? "white" : "structured");
  for (const auto& e : r.candidates) {
    if (e.ok) std::printf("  %-26s CV error %.4g  dBIC %+.4g\n", e.name.c_str(), e.cv_error, e.bic - r.base.bic);
    else std::printf("  %-26s not ranked: %s\n", e.name.c_str(), e.error.c_str());
  }
  std::printf("%s: %s\n", r.chosen >= 0 ? ("added " + r.candidates[r.chosen].name).c_str() : "nothing added", r.reason.c_str());
  std::printf("output: %s (loop.yaml, report.md, figures)\n", s.output_folder.c_str());
  return 0;
}

}  // namespace grainscale::studies
