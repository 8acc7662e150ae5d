#include "studies/hold_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <ostream>

#include "continuum/analytic_flows.hpp"
#include "continuum/integrator.hpp"
#include "continuum/term_registry.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::studies {

using continuum::closure::ClosureFlow;
using continuum::closure::FlowRecord;
using continuum::closure::FlowSample;
using continuum::closure::ShallowGranularFlow;

namespace {

continuum::closure::SectionSettings section_of(const HoldSettings& s) {
  continuum::closure::SectionSettings sec;
  sec.length = s.length;
  sec.nx = s.nx;
  sec.friction = s.friction;
  sec.ceiling = s.decked ? s.depth : std::numeric_limits<double>::infinity();
  sec.max_dt = s.chunk / 40;  // at least 40 steps per motion cycle
  return sec;
}

continuum::closure::ContainerGravity gravity_of(const HoldSettings& s) {
  continuum::closure::ContainerPlacement p;
  p.x_axis = s.direction == "longitudinal" ? dem::Vec3{1, 0, 0} : dem::Vec3{0, 1, 0};
  p.z_axis = {0, 0, 1};
  p.origin = {0, 0, 0};
  p.pivot = s.pivot_x * p.x_axis + s.pivot_z * p.z_axis;
  p.reference_height = s.fill_height;  // the flowing layer is at the surface
  return continuum::closure::ContainerGravity(s.motion, p);
}

}  // namespace

HoldModel::HoldModel(const HoldSettings& s)
    : s_(s), closure_(section_of(s), gravity_of(s), std::vector<double>(s.nx, s.fill_height)) {
  record_ = std::make_shared<FlowRecord>(s.length, s.nx);
  record_->append(continuum::closure::sample_of(closure_));
  build_model(record_);
  c_.assign(model_->size(), s.chaff_initial);
}

void HoldModel::build_model(std::shared_ptr<const FlowRecord> record) {
  if (integrator_) chaff_steps_done_ += integrator_->stats().steps;
  integrator_.reset();
  const double w = s_.window;
  auto flow = std::make_shared<ClosureFlow>(record, s_.friction.layer_depth, [w](double) { return w; });
  model_ = std::make_unique<continuum::Model>(continuum::Grid::flat(s_.length, w, s_.nx, s_.nz), flow);
  for (const auto& [name, node] : s_.terms) {
    YamlMap params(node, s_.source_file, "chaff.terms." + name);
    model_->add_term(continuum::make_term(name, params));
  }
  integrator_ = continuum::make_integrator(s_.integrator, *model_);
}

void HoldModel::build_averaged_model() {
  if (!sampler_ || sampler_->cycles() == 0) {
    // Nothing sampled (switched without start_averaging): sample the last state as one cycle.
    sampler_ = std::make_unique<continuum::closure::CycleFluxSampler>(model_->grid());
    continuum::FaceFluxes f;
    model_->face_fluxes(t_, c_, f);
    sampler_->sample(t_ - s_.chunk, f, c_);
    sampler_->sample(t_, f, c_);
    sampler_->end_cycle();
  }
  std::vector<double> vx, kx, vs, ks;
  sampler_->fit(vx, kx, vs, ks);
  if (integrator_) chaff_steps_done_ += integrator_->stats().steps;
  integrator_.reset();
  model_ = std::make_unique<continuum::Model>(model_->grid(), std::make_shared<continuum::UniformShear>(0.0));
  model_->add_term(std::make_unique<continuum::closure::CycleAveragedTransport>(vx, kx, vs, ks));
  // Implicit by default (BDF with the conservative band Jacobian, which for this linear, steady
  // model is constant): the explicit step is cfl / max_rate, and max_rate is set by the most mobile
  // face (the fitted K/A and V/A, 1e-1 to 1e1 /s in a ship's hold), not by how fast c changes.
  continuum::IntegratorSettings steady = s_.averaged_integrator;
  steady.max_dt = 0;
  integrator_ = continuum::make_integrator(steady, *model_);
  averaged_steps_before_ = chaff_steps();
  averaged_max_rate_ = model_->max_rate(t_);
}

long HoldModel::chaff_steps() const { return chaff_steps_done_ + (integrator_ ? integrator_->stats().steps : 0); }

void HoldModel::integrate(double t0, double t1, const std::vector<double>& stops,
                          const std::function<void(double)>& at_stop) {
  double t = t0;
  for (double ts : stops) {
    if (ts <= t || ts > t1) continue;
    integrator_->advance(t, ts, c_);
    t = ts;
    if (at_stop) at_stop(ts);
  }
  if (t < t1) integrator_->advance(t, t1, c_);
}

void HoldModel::resolve_chunk(const std::vector<double>& stops, const std::function<void(double)>& at_stop) {
  if (averaged_) throw std::logic_error("hold model: already switched to the averaged model");
  const double t1 = t_ + s_.chunk;
  record_->keep_last();
  closure_.advance(t1, [&](const ShallowGranularFlow& f) { record_->append(continuum::closure::sample_of(f)); });
  const FlowSample avg = continuum::closure::time_average(*record_, t_, t1);
  if (!accumulating_ || accumulated_ == 0) {
    sum_ = avg;
    accumulated_ = accumulating_ ? 1 : 0;
  } else {
    for (std::size_t f = 0; f < sum_.speed.size(); ++f) sum_.speed[f] += avg.speed[f], sum_.abs_speed[f] += avg.abs_speed[f];
    for (std::size_t i = 0; i < sum_.depth.size(); ++i) sum_.depth[i] += avg.depth[i];
    ++accumulated_;
  }
  if (accumulating_) {
    // Sample the chaff fluxes through the cycle for the slow-time model (A1).
    std::vector<double> sub = stops;
    for (int k = 1; k <= kSamplesPerCycle; ++k) sub.push_back(t_ + s_.chunk * k / kSamplesPerCycle);
    std::sort(sub.begin(), sub.end());
    sub.erase(std::unique(sub.begin(), sub.end()), sub.end());
    continuum::FaceFluxes f;
    if (sampler_->cycles() == 0) {
      model_->face_fluxes(t_, c_, f);
      sampler_->sample(t_, f, c_);
    }
    const std::vector<double> outs = stops;
    integrate(t_, t1, sub, [&](double t) {
      model_->face_fluxes(t, c_, f);
      sampler_->sample(t, f, c_);
      if (at_stop && std::find(outs.begin(), outs.end(), t) != outs.end()) at_stop(t);
    });
    sampler_->end_cycle();
  } else {
    integrate(t_, t1, stops, at_stop);
  }
  t_ = t1;
  ++chunks_;
}

void HoldModel::start_averaging() {
  sampler_ = std::make_unique<continuum::closure::CycleFluxSampler>(model_->grid());
  accumulating_ = true;
  accumulated_ = 0;
}

void HoldModel::switch_to_average() {
  average_ = sum_;
  const double n = std::max<long>(accumulated_, 1);
  for (double& v : average_.speed) v /= n;
  for (double& v : average_.abs_speed) v /= n;
  for (double& v : average_.depth) v /= n;
  average_.t = t_;
  build_averaged_model();
  averaged_ = true;
}

void HoldModel::advance_averaged(double t1, const std::vector<double>& stops, const std::function<void(double)>& at_stop) {
  if (!averaged_) throw std::logic_error("hold model: switch_to_average() first");
  integrate(t_, t1, stops, at_stop);
  t_ = t1;
}

HoldResult run_hold(const HoldSettings& s, std::unique_ptr<HoldModel>& model, std::ostream* log) {
  const auto wall0 = std::chrono::steady_clock::now();
  model = std::make_unique<HoldModel>(s);
  HoldModel& m = *model;
  HoldResult r;
  std::vector<double> stops;
  for (int j = 1; j <= s.outputs; ++j) stops.push_back(s.t_end * j / s.outputs);
  const auto record = [&](double t) {
    r.times.push_back(t);
    r.fields.push_back(m.chaff());
    r.surface.push_back(m.averaged() ? m.average().depth : m.closure().depth());
    r.averaged.push_back(m.averaged() ? 1 : 0);
  };
  record(0);
  r.chaff_initial = m.model().chaff(m.chaff());
  const long total = static_cast<long>(std::ceil(s.t_end / s.chunk - 1e-9));
  const long resolved = std::min(s.resolved_chunks, total);
  long next_report = std::max<long>(total / 10, 1);
  while (m.chunks() < resolved) {
    if (resolved < total && m.chunks() == resolved - s.average_chunks) m.start_averaging();
    m.resolve_chunk(stops, record);
    if (log && (m.chunks() % next_report == 0 || m.chunks() == resolved)) {
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
      *log << "[hold] cycle " << m.chunks() << "/" << total << " (t = " << m.time() << " s) resolved; wall " << wall
           << " s; closure steps " << m.closure_steps() << ", chaff steps " << m.chaff_steps() << "\n";
    }
  }
  r.resolved_chunks = m.chunks();
  if (m.time() < s.t_end) {
    m.switch_to_average();
    r.average_speed = m.average().speed;
    r.average_abs_speed = m.average().abs_speed;
    if (log) *log << "[hold] switched to the cycle-averaged model at t = " << m.time() << " s\n";
    const auto avg0 = std::chrono::steady_clock::now();
    m.advance_averaged(s.t_end, stops, record);
    r.averaged_wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - avg0).count();
    r.averaged_steps = m.averaged_steps();
    r.averaged_max_rate = m.averaged_max_rate();
    r.averaged_integrator = s.averaged_integrator.method;
    if (log) {
      *log << "[hold] averaged model (" << r.averaged_integrator << "): " << r.averaged_steps << " steps in "
           << r.averaged_wall_seconds << " s; stiffest cell rate " << r.averaged_max_rate << " /s\n";
    }
  }
  r.closure_steps = m.closure_steps();
  r.chaff_steps = m.chaff_steps();
  r.chaff_final = m.model().chaff(m.chaff());
  r.c_min = *std::min_element(m.chaff().begin(), m.chaff().end());
  r.c_max = *std::max_element(m.chaff().begin(), m.chaff().end());
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace grainscale::studies
