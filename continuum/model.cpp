#include "continuum/model.hpp"

#include <algorithm>

#include "dem/input_error.hpp"

namespace grainscale::continuum {

Model::Model(Grid grid, std::shared_ptr<const Flow> flow) : grid_(std::move(grid)), flow_(std::move(flow)) {
  if (!flow_) throw InputError("continuum model: no flow given");
}

void Model::add_term(std::unique_ptr<FluxTerm> term) {
  if (has_term(term->name())) throw InputError("continuum model: term '" + term->name() + "' given twice");
  terms_.push_back(std::move(term));
}

bool Model::has_term(const std::string& name) const {
  return std::any_of(terms_.begin(), terms_.end(), [&](const auto& t) { return t->name() == name; });
}

FluxTerm& Model::term(const std::string& name) {
  return const_cast<FluxTerm&>(static_cast<const Model*>(this)->term(name));
}

const FluxTerm& Model::term(const std::string& name) const {
  for (const auto& t : terms_) {
    if (t->name() == name) return *t;
  }
  throw InputError("continuum model has no term '" + name + "'");
}

std::vector<std::string> Model::parameter_names() const {
  std::vector<std::string> names;
  for (const auto& t : terms_) {
    for (const auto& p : t->parameters().all()) names.push_back(t->name() + "." + p.name);
  }
  return names;
}

namespace {
std::pair<std::string, std::string> split(const std::string& qualified) {
  const auto dot = qualified.find('.');
  if (dot == std::string::npos) {
    throw InputError("parameter '" + qualified + "' must be written term.name, e.g. segregation.S");
  }
  return {qualified.substr(0, dot), qualified.substr(dot + 1)};
}
}  // namespace

double Model::parameter(const std::string& qualified) const {
  const auto [t, p] = split(qualified);
  return term(t).parameters().get(p);
}

void Model::set_parameter(const std::string& qualified, double value) {
  const auto [t, p] = split(qualified);
  term(t).parameters().set(p, value);
}

void Model::update_faces(double t) const {
  if (faces_valid_ && (flow_->steady() || t == faces_time_)) return;
  faces_.update(grid_, *flow_, t);
  faces_time_ = t;
  faces_valid_ = true;
}

void Model::face_fluxes(double t, std::span<const double> c, FaceFluxes& out) const {
  update_faces(t);
  out.reset(grid_);
  const TermContext ctx{grid_, faces_};
  for (const auto& term : terms_) term->add_fluxes(ctx, c, out);
}

void Model::rhs(double t, std::span<const double> c, std::span<double> dcdt) const {
  face_fluxes(t, c, fluxes_);
  const Grid& g = grid_;
  if (source_ && (!source_valid_ || t != source_time_)) {
    source_values_.resize(size());
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 0; k < g.nz(); ++k) source_values_[g.index(i, k)] = source_(g.x_centre(i), g.z_centre(i, k), t);
    }
    source_time_ = t;
    source_valid_ = true;
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) {
      const double net_out = fluxes_.x[x_face(g, i + 1, k)] - fluxes_.x[x_face(g, i, k)] +
                             fluxes_.s[s_face(g, i, k + 1)] - fluxes_.s[s_face(g, i, k)];
      double v = -net_out / g.area(i, k);
      if (source_) v += source_values_[g.index(i, k)];
      dcdt[g.index(i, k)] = v;
    }
  }
}

double Model::max_rate(double t) const {
  update_faces(t);
  std::vector<double> rate(size(), 0.0);
  const TermContext ctx{grid_, faces_};
  for (const auto& term : terms_) term->add_rate_bound(ctx, rate);
  return rate.empty() ? 0.0 : *std::max_element(rate.begin(), rate.end());
}

int Model::jacobian_half_bandwidth() const {
  int bw = 0;
  for (const auto& term : terms_) bw = std::max(bw, term->jacobian_half_bandwidth(grid_));
  return std::min<int>(bw, static_cast<int>(size()) - 1);
}

double Model::chaff(std::span<const double> c) const {
  return grid_.integrate(c);
}

}  // namespace grainscale::continuum
