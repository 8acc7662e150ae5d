#include "studies/fit_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "continuum/integrator.hpp"
#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"
#include "grainscale_version.hpp"
#include "studies/fit_plots.hpp"
#include "studies/observed_fit.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;
using continuum::Model;
using continuum::SurfaceCoverage;

namespace {

/// Short names for the coefficients the issue asks to fit (docs/continuum.md).
const std::vector<std::pair<std::string, std::string>> kAliases = {
    {"S", "segregation.S"}, {"C", "shear_diffusion.C"}, {"D0", "background_diffusion.D0"}, {"kappa", "observation.kappa"}};

std::string qualified(const std::string& name) {
  for (const auto& [alias, full] : kAliases)
    if (name == alias) return full;
  return name;
}

bool is_observation(const std::string& name) { return name.rfind("observation.", 0) == 0; }

double get(const Model& m, const SurfaceCoverage& o, const std::string& name) {
  return is_observation(name) ? o.parameters().get(name.substr(12)) : m.parameter(name);
}

void set(Model& m, SurfaceCoverage& o, const std::string& name, double v) {
  if (is_observation(name)) o.parameters().set(name.substr(12), v);
  else m.set_parameter(name, v);
}

std::string unit_of(const Model& m, const SurfaceCoverage& o, const std::string& name) {
  const auto dot = name.find('.');
  const continuum::ParameterSet& set =
      is_observation(name) ? o.parameters() : m.term(name.substr(0, dot)).parameters();
  for (const auto& p : set.all())
    if (p.name == name.substr(dot + 1)) return p.unit;
  return "";
}

std::string existing(const YamlMap& m, const std::string& key, const std::string& path) {
  if (!fs::exists(path)) throw InputError(m.where(key) + ": cannot find '" + path + "'");
  return path;
}

std::string g(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

/// A double-quoted YAML scalar.
std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string short_g(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

std::vector<std::string> fittable_parameters(const continuum::ContinuumSettings& model_settings) {
  const Model model = continuum::build_model(model_settings);
  std::vector<std::string> allowed;
  for (const auto& [alias, full] : kAliases) allowed.push_back(alias);
  for (const auto& n : model.parameter_names()) allowed.push_back(n);
  allowed.push_back("observation.kappa");
  allowed.push_back("observation.delta");
  return allowed;
}

namespace {

void read_fit(YamlMap f, FitCommandSettings& s) {
  const Model model = continuum::build_model(s.model);
  SurfaceCoverage observation(s.model.kappa, s.model.delta);
  const std::vector<std::string> allowed = fittable_parameters(s.model);
  for (const std::string& name : f.choices_or_empty("parameters", allowed)) {
    const std::string q = qualified(name);
    if (!is_observation(q) && !model.has_term(q.substr(0, q.find('.')))) {
      throw InputError(f.where("parameters") + ": '" + name + "' is " + q + ", but the model (" + s.model_file +
                       ") has no " + q.substr(0, q.find('.')) + " term");
    }
    if (std::count(s.fit.parameters.begin(), s.fit.parameters.end(), q)) {
      throw InputError(f.where("parameters") + ": " + q + " is listed twice");
    }
    if (is_observation(q) && s.data.coverage.empty()) {
      throw InputError(f.where("parameters") + ": " + q + " is seen only through coverage data; give data.coverage");
    }
    s.fit.parameters.push_back(q);
  }
  if (s.fit.parameters.empty()) throw InputError(f.where("parameters") + ": list the parameters to fit, e.g. [S, C, D0, kappa]");
  if (auto start = f.optional_map("start")) {
    Model trial = continuum::build_model(s.model);
    for (const std::string& key : start->keys()) {
      const std::string q = qualified(key);
      if (!std::count(s.fit.parameters.begin(), s.fit.parameters.end(), q)) {
        throw InputError(start->where(key) + ": '" + key + "' is not among the fitted parameters");
      }
      const double v = start->number(key, Range::positive());
      try {
        set(trial, observation, q, v);  // the admissible range
      } catch (const InputError& e) {
        throw InputError(start->where(key) + ": " + e.what());
      }
      s.start[q] = v;
    }
    start->finish();
  }
  s.fit.max_iterations = static_cast<int>(f.integer_or("max_iterations", 100, 1, 100000));
  // Fixed explicit steps by default: CVODE's adaptive steps make the forward map too rough for
  // the finite-difference Jacobian (continuum/fit.hpp).
  s.fit.integrator = s.model.integrator;
  s.fit.integrator.method = f.choice_or("integrator", "ssp_rk3", continuum::integrator_names());
  s.fit.integrator.cfl = f.number_or("cfl", 0.4, {0, 1, true, false});
  s.fit.integrator.max_dt = f.number_or("max_dt", 0.0, Range::non_negative());
  s.fit.fd_step = f.number_or("fd_step", 1e-6, {0, 0.1, true, false});
  f.finish();
}

/// The integrator of the fit with its step fixed from the starting values (as continuum::fit
/// does), so the fit and the figures run the same forward map.
continuum::IntegratorSettings fixed_step(const Model& model, double t0, const Observations& data,
                                         continuum::IntegratorSettings s) {
  if (s.method == "ssp_rk3" && s.max_dt <= 0) {
    const double rate = model.max_rate(t0);
    s.max_dt = rate > 0 ? 0.5 * s.cfl / rate : data.times.back() - t0;
  }
  return s;
}

/// Signs that a fit is not to be trusted. A parameter that ran off by many orders of magnitude
/// (towards 0 in log space), has no finite, non-zero standard error, or one above its value, is
/// not constrained by the data: its Jacobian column is (nearly) zero.
std::vector<std::string> trust_warnings(const continuum::FitResult& r, const std::vector<double>& start) {
  std::vector<std::string> w;
  if (!r.converged) w.push_back("the fit did not converge (GSL: " + r.status + ")");
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    const double ratio = r.values[j] / start[j];
    if (!(ratio > 1e-6 && ratio < 1e6)) {
      w.push_back(r.names[j] + " ran from " + short_g(start[j]) + " to " + short_g(r.values[j]) +
                  ": the data do not constrain it (or do not need the term)");
    } else if (!(r.standard_errors[j] > 0) || !std::isfinite(r.standard_errors[j])) {
      w.push_back(r.names[j] + " has no finite standard error: the data do not constrain it");
    } else if (r.standard_errors[j] > r.values[j]) {
      // sigma of log(value) > 1: not even the factor e is known.
      w.push_back(r.names[j] + " = " + short_g(r.values[j]) + " +- " + short_g(r.standard_errors[j]) +
                  ": the standard error exceeds the value, the data hardly constrain it");
    }
  }
  return w;
}

std::string yaml_list(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t k = 0; k < v.size(); ++k) s += (k ? ", " : "") + g(v[k]);
  return s + "]";
}

std::string fit_yaml(const FitCommandSettings& s, const FitCommandSummary& sum, const Observations& data,
                     const std::vector<std::string>& units) {
  const continuum::FitResult& r = sum.result;
  std::ostringstream y;
  y << "# grainscale fit (" << version << " " << git_revision << "): continuum coefficients fitted to data\n"
    << "settings: " << quoted(s.source_file) << "\n"
    << "model: " << quoted(s.model_file) << "\n"
    << "status: " << r.status << "   # GSL trust-region Levenberg-Marquardt on log(parameter)\n"
    << "converged: " << (r.converged ? "true" : "false") << "\n"
    << "iterations: " << r.iterations << "\n"
    << "chi2: " << g(r.chi2) << "   # sum of ((model - data) / sigma)^2\n"
    << "observations: " << r.residuals << "\n"
    << "dof: " << r.dof << "\n"
    << "chi2_per_dof: " << g(r.chi2 / r.dof) << "\n"
    << "noise: " << (data.sigma_known ? "given   # standard errors from (J^T J)^-1" : "estimated   # no sigma: standard errors scaled by chi2/dof") << "\n"
    << "warnings:" << (sum.warnings.empty() ? " []" : "") << "\n";
  for (const auto& w : sum.warnings) y << "  - " << quoted(w) << "\n";
  y << "parameters:\n";
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    y << "  " << r.names[j] << ": {value: " << g(r.values[j]) << ", standard_error: " << g(r.standard_errors[j])
      << ", start: " << g(sum.start_values[j]) << ", unit: \"" << units[j] << "\"}\n";
  }
  y << "correlation:   # rows and columns in the order of parameters\n";
  for (const auto& row : r.correlation) y << "  - " << yaml_list(row) << "\n";
  y << "data:\n"
    << "  fields: " << quoted(s.data.fields) << "\n"
    << "  coverage: " << quoted(s.data.coverage) << "\n"
    << "  t0: " << g(s.t0) << "\n"
    << "  min_solid_fraction: " << g(s.data.min_solid_fraction) << "\n"
    << "  from: " << g(s.data.from) << "\n"
    << "  times: " << yaml_list(data.times) << "\n"
    << "  field_rows: " << data.field_rows << "\n"
    << "  field_cells: " << data.fields.size() << "   # (time, cell) values after combining rows per nearest cell\n"
    << "  coverage_rows: " << data.coverage_rows << "\n"
    << "  coverage_columns: " << data.coverage.size() << "\n";
  return y.str();
}

std::string report_md(const FitCommandSettings& s, const FitCommandSummary& sum, const Observations& data,
                      const std::vector<std::string>& units, const std::vector<std::string>& figures, double seconds) {
  const continuum::FitResult& r = sum.result;
  std::ostringstream m;
  m << "# Continuum fit\n\n"
    << "Settings `" << s.source_file << "`, model `" << s.model_file << "`. grainscale " << version << " (" << git_revision
    << ").\n\n"
    << "**" << (r.converged ? "Converged" : "Not converged") << "** (GSL: " << r.status << ") after " << r.iterations
    << " iterations in " << short_g(seconds) << " s. chi2 = " << short_g(r.chi2) << " for " << r.residuals
    << " observations and " << r.names.size() << " parameters: **chi2/dof = " << short_g(r.chi2 / r.dof) << "**";
  if (data.sigma_known) {
    m << " (about 1 when the model explains the data down to the stated noise).\n\n";
  } else {
    m << ". No sigma was given, so the points weigh equally and the standard errors below are scaled by chi2/dof.\n\n";
  }
  if (!sum.warnings.empty()) {
    m << "**Do not use these values as they are:**\n\n";
    for (const auto& w : sum.warnings) m << "- " << w << "\n";
    m << "\n";
  }
  m << "| parameter | unit | start | fitted | standard error | relative |\n|---|---|---|---|---|---|\n";
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    m << "| `" << r.names[j] << "` | " << units[j] << " | " << short_g(sum.start_values[j]) << " | " << short_g(r.values[j])
      << " | " << short_g(r.standard_errors[j]) << " | " << short_g(100 * r.standard_errors[j] / r.values[j]) << " % |\n";
  }
  if (r.names.size() > 1) {
    m << "\nCorrelations (of the log-parameters; near +-1: the data do not tell the two apart):\n\n|   |";
    for (const auto& n : r.names) m << " `" << n << "` |";
    m << "\n|---|";
    for (std::size_t j = 0; j < r.names.size(); ++j) m << "---|";
    m << "\n";
    for (std::size_t a = 0; a < r.names.size(); ++a) {
      m << "| `" << r.names[a] << "` |";
      for (std::size_t b = 0; b < r.names.size(); ++b) m << " " << short_g(r.correlation[a][b]) << " |";
      m << "\n";
    }
  }
  m << "\n## Data\n\n";
  if (!s.data.fields.empty()) {
    m << "- fields `" << s.data.fields << "`: " << data.field_rows << " rows with a value, combined into " << data.fields.size()
      << " (time, cell) observations.\n";
  }
  if (!s.data.coverage.empty()) {
    m << "- coverage `" << s.data.coverage << "`: " << data.coverage_rows << " rows with a value, combined into "
      << data.coverage.size() << " (time, column) observations.\n";
  }
  m << "- " << data.times.size() << " times from " << short_g(data.times.front()) << " to " << short_g(data.times.back())
    << " s; the model starts from its `initial` field at t0 = " << short_g(s.t0) << " s.\n"
    << "- Each point goes to its nearest model cell (the column holding x, the layer whose centre is nearest to z);"
       " points in one cell at one time are combined by their inverse-variance weighted mean.\n"
    << "\n## Figures\n\n";
  for (const auto& f : figures) m << "![" << f << "](" << f << ")\n\n";
  return m.str();
}

}  // namespace

FitCommandSettings load_fit_command_settings(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  FitCommandSettings s;
  s.source_file = file;
  {
    const YAML::Node raw = YAML::LoadFile(file)["model"];
    if (raw && !raw.IsScalar()) {
      throw InputError(root.where("model") + ": give the continuum settings as a file name (model: continuum.yaml)");
    }
    s.model_file = existing(root, "model", resolve_beside(file, root.string("model")));
    s.model = continuum::load_continuum_settings(s.model_file);
  }
  {
    YamlMap d = root.map("data");
    if (d.has("fields")) s.data.fields = existing(d, "fields", resolve_beside(file, d.string("fields")));
    if (d.has("field_sigma")) s.data.field_sigma = d.number("field_sigma", Range::positive());
    if (d.has("coverage")) s.data.coverage = existing(d, "coverage", resolve_beside(file, d.string("coverage")));
    if (d.has("coverage_sigma")) s.data.coverage_sigma = d.number("coverage_sigma", Range::positive());
    s.t0 = d.number_or("t0", 0.0, Range::non_negative());
    s.data.from = d.number_or("from", 0.0, Range::non_negative());
    if (d.has("min_solid_fraction")) {
      if (s.data.fields.empty()) throw InputError(d.where("min_solid_fraction") + ": applies to 'fields' data only");
      s.data.min_solid_fraction = d.number("min_solid_fraction", Range::closed(0, 1));
    }
    if (s.data.fields.empty() && s.data.coverage.empty()) {
      throw InputError(root.where("data") + ": give 'fields' (t_s,x_m,z_m,c[,sigma]) and/or 'coverage' (t_s,x_m,coverage[,sigma])");
    }
    d.finish();
  }
  read_fit(root.map("fit"), s);
  s.output_folder = resolve_beside(file, root.string("output"));
  root.finish();
  return s;
}

FitCommandSummary run_fit_command(const FitCommandSettings& s) {
  const auto t_start = std::chrono::steady_clock::now();
  Model model = continuum::build_model(s.model);
  SurfaceCoverage observation(s.model.kappa, s.model.delta);
  for (const auto& [name, v] : s.start) set(model, observation, name, v);
  const continuum::Grid& grid = model.grid();
  const Observations data = map_observations(s.data, grid, s.t0);
  const ModelStart start{continuum::initial_field(s.model, grid), s.t0, s.model.stops};

  FitCommandSummary sum;
  std::vector<std::string> units;
  for (const auto& n : s.fit.parameters) {
    sum.start_values.push_back(get(model, observation, n));
    units.push_back(unit_of(model, observation, n));
  }
  continuum::FitSettings settings = s.fit;
  settings.integrator = fixed_step(model, s.t0, data, s.fit.integrator);
  sum.result = fit_observations(model, observation, start, data, settings);
  sum.warnings = trust_warnings(sum.result, sum.start_values);
  sum.field_observations = data.fields.size();
  sum.coverage_observations = data.coverage.size();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  // Figures at the optimum, with the fit's own forward map.
  fs::create_directories(s.output_folder);
  const Prediction p = predict(model, observation, start, data.times, settings.integrator);
  std::vector<std::string> figures;
  auto save = [&](const Image& img, const std::string& name) {
    img.write_png((fs::path(s.output_folder) / name).string());
    figures.push_back(name);
  };
  if (!data.fields.empty()) {
    const auto ft = field_times(data);
    if (ft.size() > 1) save(field_comparison(grid, data, p, ft.front()), "fields_first.png");
    save(field_comparison(grid, data, p, ft.back()), "fields_last.png");
  }
  if (!data.coverage.empty()) {
    save(draw(coverage_comparison(grid, data, p)), "coverage.png");
    save(draw(coverage_residuals(grid, data, p)), "coverage_residual.png");
  }
  save(draw(residual_histogram(observation_residuals(p, data))), "residuals.png");

  const std::string yaml = (fs::path(s.output_folder) / "fit.yaml").string();
  const std::string md = (fs::path(s.output_folder) / "report.md").string();
  dem::write_file_atomically(yaml, fit_yaml(s, sum, data, units));
  dem::write_file_atomically(md, report_md(s, sum, data, units, figures, seconds));
  sum.files = {yaml, md};
  for (const auto& f : figures) sum.files.push_back((fs::path(s.output_folder) / f).string());
  return sum;
}

int fit_command(const std::vector<std::string>& positional, const std::string& out) {
  if (positional.size() != 1) throw InputError("usage: grainscale fit SETTINGS.yaml [--out DIR]");
  FitCommandSettings s = load_fit_command_settings(positional[0]);
  if (!out.empty()) s.output_folder = out;
  const FitCommandSummary sum = run_fit_command(s);
  const continuum::FitResult& r = sum.result;
  std::printf("fit %s after %d iterations: chi2/dof = %.4g (%d observations: %zu field cells, %zu coverage columns; %zu parameters)\n",
              r.converged ? "converged" : "did NOT converge", r.iterations, r.chi2 / r.dof, r.residuals,
              sum.field_observations, sum.coverage_observations, r.names.size());
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    std::printf("  %-26s = %.5g +- %.2g (start %.4g)\n", r.names[j].c_str(), r.values[j], r.standard_errors[j],
                sum.start_values[j]);
  }
  for (const auto& w : sum.warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("output: %s (fit.yaml, report.md, %zu figures)\n", s.output_folder.c_str(), sum.files.size() - 2);
  return sum.warnings.empty() ? 0 : 4;
}

}  // namespace grainscale::studies
