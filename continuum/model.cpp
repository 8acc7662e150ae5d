#include "continuum/model.hpp"

#include <algorithm>
#include <cmath>

#include "continuum/conservative_jacobian.hpp"
#include "continuum/depth_averaged.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

Model::Model(Grid grid, std::shared_ptr<const Flow> flow, Closure closure)
    : grid_(std::move(grid)), flow_(std::move(flow)), closure_(closure), current_(grid_) {
  if (!flow_) throw InputError("continuum model: no flow given");
  if (closure_ == Closure::depth_averaged) depth_averaged_ = std::make_unique<DepthAveraged>(grid_);
}

Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;

void Model::add_term(std::unique_ptr<FluxTerm> term) {
  if (has_term(term->name())) throw InputError("continuum model: term '" + term->name() + "' given twice");
  if (closure_ == Closure::depth_averaged && !DepthAveraged::supports(term->name())) {
    throw InputError("continuum model: term '" + term->name() + "' has no depth-averaged form (model type " +
                     "depth_averaged takes " + DepthAveraged::supported_terms() + ")");
  }
  terms_.push_back(std::move(term));
}

void Model::set_cycle_average(double period, int phases) {
  if (closure_ != Closure::depth_averaged) throw InputError("continuum model: cycle averaging needs the depth-averaged closure");
  depth_averaged_->set_cycle_average(period, phases);
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

std::vector<const FluxTerm*> Model::terms() const {
  std::vector<const FluxTerm*> out;
  for (const auto& t : terms_) out.push_back(t.get());
  return out;
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

/// h at the column faces at time t.
std::vector<double> surface_nodes(const Flow& flow, const Grid& g, double t) {
  std::vector<double> h(static_cast<std::size_t>(g.nx()) + 1);
  for (int f = 0; f <= g.nx(); ++f) h[f] = flow.surface_height(g.x_face(f), t);
  return h;
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
  if (flow_->moving_surface()) {
    // Nodes follow h(x, t); the column depths (areas) are set from the state by set_geometry().
    current_ = Grid(grid_.length(), grid_.nx(), grid_.nz(), surface_nodes(*flow_, grid_, t), current_.column_depths());
  }
  faces_.update(current_, *flow_, t);
  faces_time_ = t;
  faces_valid_ = true;
}

void Model::face_fluxes(double t, std::span<const double> c, FaceFluxes& out, TermPart part) const {
  update_faces(t);
  out.reset(current_);
  const TermContext ctx{current_, faces_};
  for (const auto& term : terms_) {
    if (part == TermPart::explicit_part && term->implicit_in_imex()) continue;
    if (part == TermPart::implicit_part && !term->implicit_in_imex()) continue;
    term->add_fluxes(ctx, c, out);
  }
}

void Model::evaluate_source(double t, const Grid& g) const {
  if (!source_ || (source_valid_ && t == source_time_)) return;
  source_values_.resize(size());
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) source_values_[g.index(i, k)] = source_(g.x_centre(i), g.z_centre(i, k), t);
  }
  source_time_ = t;
  source_valid_ = true;
}

void Model::rhs(double t, std::span<const double> c, std::span<double> dcdt) const {
  face_fluxes(t, c, fluxes_);
  const Grid& g = current_;
  evaluate_source(t, g);
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
  if (closure_ == Closure::depth_averaged) {
    return depth_averaged_->max_rate(surface_grid(t), *flow_, t, DepthAveraged::coefficients(*this));
  }
  update_faces(t);
  std::vector<double> rate(size(), 0.0);
  const TermContext ctx{current_, faces_};
  for (const auto& term : terms_) term->add_rate_bound(ctx, rate);
  return rate.empty() ? 0.0 : *std::max_element(rate.begin(), rate.end());
}

int Model::jacobian_half_bandwidth() const {
  int bw = 0;
  for (const auto& term : terms_) bw = std::max(bw, term->jacobian_half_bandwidth(grid_));
  return std::min<int>(bw, static_cast<int>(size()) - 1);
}

double Model::chaff(std::span<const double> c) const { return grid_.integrate(c); }

// ---------------------------------------------------------------------------------------------
// State

namespace {
/// Moving surface: index of cell (i, k) and of column area i in the interleaved state.
std::size_t m_index(const Grid& g, int i, int k) { return static_cast<std::size_t>(i) * (g.nz() + 1) + k; }
std::size_t a_index(const Grid& g, int i) { return static_cast<std::size_t>(i) * (g.nz() + 1) + g.nz(); }
}  // namespace

std::size_t Model::state_size() const {
  if (closure_ == Closure::depth_averaged) return static_cast<std::size_t>(grid_.nx());
  if (flow_->moving_surface()) return static_cast<std::size_t>(grid_.nx()) * (grid_.nz() + 1);
  return size();
}

Grid Model::surface_grid(double t) const {
  if (!flow_->moving_surface()) return grid_;
  return Grid(grid_.length(), grid_.nx(), grid_.nz(), surface_nodes(*flow_, grid_, t));
}

Grid Model::grid_of(double t, std::span<const double> y) const {
  if (!flow_->moving_surface() || closure_ == Closure::depth_averaged) return surface_grid(t);
  std::vector<double> depth(static_cast<std::size_t>(grid_.nx()));
  for (int i = 0; i < grid_.nx(); ++i) depth[i] = y[a_index(grid_, i)] / grid_.dx();
  return Grid(grid_.length(), grid_.nx(), grid_.nz(), surface_nodes(*flow_, grid_, t), std::move(depth));
}

std::vector<double> Model::state(double t, std::span<const double> c) const {
  if (c.size() != size()) throw std::invalid_argument("continuum model: c has the wrong size");
  const Grid g = surface_grid(t);
  if (closure_ == Closure::depth_averaged) return depth_averaged_->inventory(g, c);
  if (!flow_->moving_surface()) return {c.begin(), c.end()};
  std::vector<double> y(state_size());
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) y[m_index(g, i, k)] = g.area(i, k) * c[g.index(i, k)];
    y[a_index(g, i)] = g.dx() * g.h_column(i);
  }
  return y;
}

std::vector<double> Model::concentration(double t, std::span<const double> y) const {
  if (closure_ == Closure::depth_averaged) {
    const Grid g = surface_grid(t);
    return depth_averaged_->concentration(g, *flow_, t, DepthAveraged::coefficients(*this), y);
  }
  if (!flow_->moving_surface()) return {y.begin(), y.end()};
  const Grid& g = grid_;
  std::vector<double> c(size());
  for (int i = 0; i < g.nx(); ++i) {
    const double area = g.dsigma() * y[a_index(g, i)];
    for (int k = 0; k < g.nz(); ++k) c[g.index(i, k)] = y[m_index(g, i, k)] / area;
  }
  return c;
}

double Model::state_chaff(std::span<const double> y) const {
  if (closure_ == Closure::depth_averaged) {
    double total = 0;
    for (double v : y) total += v;
    return total * grid_.dx();
  }
  if (!flow_->moving_surface()) return chaff(y);
  double total = 0;
  for (int i = 0; i < grid_.nx(); ++i) {
    double column = 0;
    for (int k = 0; k < grid_.nz(); ++k) column += y[m_index(grid_, i, k)];
    total += column;
  }
  return total;
}

void Model::set_geometry(double t, std::span<const double> y) const {
  // Column depths from the state; the nodes are set (per t) by update_faces().
  std::vector<double> depth(static_cast<std::size_t>(grid_.nx()));
  for (int i = 0; i < grid_.nx(); ++i) depth[i] = y[a_index(grid_, i)] / grid_.dx();
  update_faces(t);
  current_ = Grid(grid_.length(), grid_.nx(), grid_.nz(), current_.surface_nodes(), std::move(depth));
  c_scratch_.resize(size());
  for (int i = 0; i < grid_.nx(); ++i) {
    for (int k = 0; k < grid_.nz(); ++k) c_scratch_[current_.index(i, k)] = y[m_index(grid_, i, k)] / current_.area(i, k);
  }
}

void Model::state_rhs(double t, std::span<const double> y, std::span<double> dydt, TermPart part) const {
  if (closure_ == Closure::depth_averaged) {
    // Not split: the whole 1-D rhs is the implicit part of an IMEX integrator.
    if (part == TermPart::explicit_part) {
      std::fill(dydt.begin(), dydt.end(), 0.0);
      return;
    }
    depth_averaged_->rhs(surface_grid(t), *flow_, t, DepthAveraged::coefficients(*this), y, dydt);
    return;
  }
  const bool with_source = source_ && part != TermPart::implicit_part;
  if (!flow_->moving_surface()) {
    face_fluxes(t, y, fluxes_, part);
    const Grid& g = current_;
    if (with_source) evaluate_source(t, g);
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 0; k < g.nz(); ++k) {
        const double net_out = fluxes_.x[x_face(g, i + 1, k)] - fluxes_.x[x_face(g, i, k)] +
                               fluxes_.s[s_face(g, i, k + 1)] - fluxes_.s[s_face(g, i, k)];
        double v = -net_out / g.area(i, k);
        if (with_source) v += source_values_[g.index(i, k)];
        dydt[g.index(i, k)] = v;
      }
    }
    return;
  }
  // (M2): d(A c)/dt = −Σ F(c; Q_rel) + A s,  da/dt = ȧ.
  set_geometry(t, y);
  const Grid& g = current_;
  face_fluxes(t, c_scratch_, fluxes_, part);
  if (with_source) evaluate_source(t, surface_grid(t));
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) {
      const double net_out = fluxes_.x[x_face(g, i + 1, k)] - fluxes_.x[x_face(g, i, k)] +
                             fluxes_.s[s_face(g, i, k + 1)] - fluxes_.s[s_face(g, i, k)];
      double v = -net_out;
      if (with_source) v += g.area(i, k) * source_values_[g.index(i, k)];
      dydt[m_index(g, i, k)] = v;
    }
    dydt[a_index(g, i)] = part == TermPart::implicit_part ? 0.0 : faces_.column_area_rate[i];
  }
}

double Model::state_max_rate(double t, std::span<const double> y) const {
  if (flow_->moving_surface() && closure_ == Closure::resolved) set_geometry(t, y);
  return max_rate(t);
}

std::vector<double> Model::state_scale() const {
  const Grid& g = grid_;
  if (closure_ == Closure::depth_averaged) return std::vector<double>(g.column_depths());
  if (!flow_->moving_surface()) return std::vector<double>(size(), 1.0);
  std::vector<double> s(state_size());
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) s[m_index(g, i, k)] = g.area(i, k);
    s[a_index(g, i)] = g.dx() * g.h_column(i);
  }
  return s;
}

int Model::state_half_bandwidth() const {
  if (closure_ == Closure::depth_averaged) return std::min(DepthAveraged::half_bandwidth(), static_cast<int>(state_size()) - 1);
  const int b = jacobian_half_bandwidth();
  if (!flow_->moving_surface()) return b;
  const int nz = grid_.nz();
  // A c-index distance b spans up to b / nz + 1 columns, each one entry longer in the state, and a
  // column's area couples to every cell of the columns within reach.
  return std::min(b + b / nz + 2 * nz + 2, static_cast<int>(state_size()) - 1);
}

void Model::state_jacobian(double t, std::span<const double> y, int b,
                           const std::function<void(std::size_t, std::size_t, double)>& add, TermPart part) const {
  if (closure_ == Closure::depth_averaged) {
    if (part == TermPart::explicit_part) return;
    depth_averaged_->jacobian(surface_grid(t), *flow_, t, DepthAveraged::coefficients(*this), y, b, add);
    return;
  }
  if (!flow_->moving_surface()) {
    conservative_band_jacobian(*this, t, y, b, add, part);
    return;
  }
  // Chain rule through c = m / (dσ a): with G = ∂(dm/dt)/∂c (face-flux difference quotients),
  //   ∂(dm_r/dt)/∂m_j = G_rj / A_j,   ∂(dm_r/dt)/∂a_i = −Σ_{j in column i} G_rj c_j / a_i.
  // Both keep Σ_r J = 0 (each face's derivative enters its two cells with opposite signs). The a
  // rows are zero: da/dt does not depend on the state.
  set_geometry(t, y);
  const Grid g = current_;
  const std::vector<double> c = c_scratch_;
  const int nz = g.nz();
  conservative_flux_jacobian(*this, t, c, jacobian_half_bandwidth(), part, [&](std::size_t row, std::size_t col, double dF) {
    const int ri = static_cast<int>(row) / nz, rk = static_cast<int>(row) % nz;
    const int ci = static_cast<int>(col) / nz, ck = static_cast<int>(col) % nz;
    const std::size_t r = m_index(g, ri, rk), m = m_index(g, ci, ck), a = a_index(g, ci);
    const auto within = [&](std::size_t p, std::size_t q) { return (p > q ? p - q : q - p) <= static_cast<std::size_t>(b); };
    if (within(r, m)) add(r, m, dF / g.area(ci, ck));
    if (within(r, a)) add(r, a, -dF * c[col] / (g.dx() * g.h_column(ci)));
  });
}

}  // namespace grainscale::continuum
