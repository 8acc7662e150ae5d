#include "studies/fit_observations.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "dem/input_error.hpp"
#include "studies/numeric_csv.hpp"

namespace grainscale::studies {

namespace {

/// Inverse-variance sums per (time, index) before they become Observations.
struct Sums {
  double weight = 0, weighted = 0;
  int points = 0;
};

struct Rows {
  std::vector<double> t, x, z, value, sigma;
  std::vector<int> line;
  std::string file;
};

/// The rows with a finite value, checked; `z_column` empty for coverage.
Rows read_rows(const std::string& file, const std::string& value_column, bool with_z, std::optional<double> default_sigma,
               bool& sigma_known, double min_solid_fraction, double from) {
  const NumericCsv csv = NumericCsv::load(file);
  if (min_solid_fraction > 0 && !csv.has("phi")) {
    throw InputError(file + ": data.min_solid_fraction needs a 'phi' column (the solid volume fraction; a grainscale cg fields.csv has one)");
  }
  const auto phi = min_solid_fraction > 0 ? csv.column("phi") : std::vector<double>(csv.rows(), 1.0);
  const auto t = csv.column("t_s"), x = csv.column("x_m"), v = csv.column(value_column);
  const auto z = with_z ? csv.column("z_m") : std::vector<double>(csv.rows(), 0.0);
  const bool has_sigma = csv.has("sigma");
  const auto s = has_sigma ? csv.column("sigma") : std::vector<double>(csv.rows(), default_sigma.value_or(1.0));
  if (!has_sigma && !default_sigma) sigma_known = false;
  Rows r;
  r.file = file;
  for (std::size_t k = 0; k < csv.rows(); ++k) {
    if (std::isnan(v[k])) continue;  // no data here
    if (!(phi[k] >= min_solid_fraction)) continue;  // above the bed (or no solid): not data
    if (t[k] < from) continue;                       // before data.from: not data
    const std::string where = file + ":" + std::to_string(csv.line(k)) + ": ";
    if (!std::isfinite(v[k])) throw InputError(where + value_column + " must be finite or nan");
    if (!std::isfinite(t[k]) || !std::isfinite(x[k]) || !std::isfinite(z[k])) {
      throw InputError(where + "t_s, x_m" + (with_z ? ", z_m" : "") + " must be finite where " + value_column + " is given");
    }
    if (!(s[k] > 0) || !std::isfinite(s[k])) throw InputError(where + "sigma must be positive and finite");
    r.t.push_back(t[k]);
    r.x.push_back(x[k]);
    r.z.push_back(z[k]);
    r.value.push_back(v[k]);
    r.sigma.push_back(s[k]);
    r.line.push_back(csv.line(k));
  }
  return r;
}

int column_of(const continuum::Grid& g, double x, const std::string& where) {
  if (x < -0.5 * g.dx() || x > g.length() + 0.5 * g.dx()) {
    throw InputError(where + "x_m = " + std::to_string(x) + " is outside the model bed [0, " + std::to_string(g.length()) +
                     "] m by more than half a column (units?)");
  }
  return std::clamp(static_cast<int>(std::floor(x / g.dx())), 0, g.nx() - 1);
}

int layer_of(const continuum::Grid& g, int i, double z, const std::string& where) {
  const double h = g.h_column(i);
  if (z < -h || z > 2 * h) {
    throw InputError(where + "z_m = " + std::to_string(z) + " is more than a bed depth (" + std::to_string(h) +
                     " m) outside the bed (units?)");
  }
  return std::clamp(static_cast<int>(std::floor(z / h / g.dsigma())), 0, g.nz() - 1);
}

std::vector<Observation> combine(const std::map<std::pair<double, std::size_t>, Sums>& sums, const std::vector<double>& times) {
  std::vector<Observation> out;
  for (const auto& [key, s] : sums) {
    Observation o;
    o.time = static_cast<std::size_t>(std::lower_bound(times.begin(), times.end(), key.first) - times.begin());
    o.index = key.second;
    o.value = s.weighted / s.weight;
    o.sigma = 1 / std::sqrt(s.weight);
    o.points = s.points;
    out.push_back(o);
  }
  return out;
}

}  // namespace

Observations map_observations(const ObservationFiles& files, const continuum::Grid& g, double t0) {
  if (files.fields.empty() && files.coverage.empty()) throw InputError("fit data: give a fields and/or a coverage file");
  Observations obs;
  bool field_sigma = true, coverage_sigma = true;
  Rows fields, coverage;
  if (!files.fields.empty()) fields = read_rows(files.fields, "c", true, files.field_sigma, field_sigma, files.min_solid_fraction, files.from);
  if (!files.coverage.empty()) coverage = read_rows(files.coverage, "coverage", false, files.coverage_sigma, coverage_sigma, 0, files.from);
  if (!files.fields.empty() && !files.coverage.empty() && !(field_sigma && coverage_sigma)) {
    throw InputError("fit data: with both fields and coverage, give each a sigma (a sigma column or the sigma key): "
                     "their relative weight in the fit depends on it");
  }
  obs.sigma_known = field_sigma && coverage_sigma;

  for (const Rows* r : {&fields, &coverage}) {
    for (std::size_t k = 0; k < r->t.size(); ++k) {
      if (!(r->t[k] > t0)) {
        throw InputError(r->file + ":" + std::to_string(r->line[k]) + ": t_s = " + std::to_string(r->t[k]) +
                         " is not after the model's start t0 = " + std::to_string(t0) +
                         " (the model starts from its own initial field there)");
      }
      obs.times.push_back(r->t[k]);
    }
  }
  std::sort(obs.times.begin(), obs.times.end());
  obs.times.erase(std::unique(obs.times.begin(), obs.times.end()), obs.times.end());

  std::map<std::pair<double, std::size_t>, Sums> field_sums, coverage_sums;
  for (std::size_t k = 0; k < fields.t.size(); ++k) {
    const std::string where = fields.file + ":" + std::to_string(fields.line[k]) + ": ";
    const int i = column_of(g, fields.x[k], where);
    const int layer = layer_of(g, i, fields.z[k], where);
    Sums& s = field_sums[{fields.t[k], g.index(i, layer)}];
    const double w = 1 / (fields.sigma[k] * fields.sigma[k]);
    s.weight += w;
    s.weighted += w * fields.value[k];
    ++s.points;
  }
  for (std::size_t k = 0; k < coverage.t.size(); ++k) {
    const std::string where = coverage.file + ":" + std::to_string(coverage.line[k]) + ": ";
    Sums& s = coverage_sums[{coverage.t[k], static_cast<std::size_t>(column_of(g, coverage.x[k], where))}];
    const double w = 1 / (coverage.sigma[k] * coverage.sigma[k]);
    s.weight += w;
    s.weighted += w * coverage.value[k];
    ++s.points;
  }
  obs.fields = combine(field_sums, obs.times);
  obs.coverage = combine(coverage_sums, obs.times);
  obs.field_rows = fields.t.size();
  obs.coverage_rows = coverage.t.size();
  if (obs.fields.empty() && obs.coverage.empty()) {
    throw InputError("fit data: no finite values in " + (files.fields.empty() ? files.coverage : files.fields) +
                     (files.fields.empty() || files.coverage.empty() ? "" : " or " + files.coverage));
  }
  return obs;
}

}  // namespace grainscale::studies
