#include "continuum/closure/flow_record.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainscale::continuum::closure {

FlowSample sample_of(const ShallowGranularFlow& flow) {
  FlowSample s;
  s.t = flow.time();
  s.speed = flow.surface_speed();
  s.abs_speed.resize(s.speed.size());
  for (std::size_t f = 0; f < s.speed.size(); ++f) s.abs_speed[f] = std::abs(s.speed[f]);
  s.depth = flow.depth();
  return s;
}

void FlowRecord::append(FlowSample s) {
  if (static_cast<int>(s.speed.size()) != nx_ + 1 || static_cast<int>(s.abs_speed.size()) != nx_ + 1 ||
      static_cast<int>(s.depth.size()) != nx_) {
    throw std::invalid_argument("flow record: sample of the wrong size");
  }
  if (!samples_.empty() && !(s.t > samples_.back().t)) throw std::invalid_argument("flow record: times must increase");
  samples_.push_back(std::move(s));
}

void FlowRecord::keep_last() {
  if (samples_.size() > 1) samples_.erase(samples_.begin(), samples_.end() - 1);
}

namespace {
void blend(const std::vector<double>& a, const std::vector<double>& b, double w, std::vector<double>& out) {
  out.resize(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) out[k] = (1 - w) * a[k] + w * b[k];
}
}  // namespace

void FlowRecord::at(double t, FlowSample& out) const {
  if (samples_.empty()) throw std::logic_error("flow record: no samples");
  out.t = t;
  if (samples_.size() == 1 || t <= samples_.front().t) {
    const FlowSample& s = samples_.front();
    out.speed = s.speed, out.abs_speed = s.abs_speed, out.depth = s.depth;
    return;
  }
  if (t >= samples_.back().t) {
    const FlowSample& s = samples_.back();
    out.speed = s.speed, out.abs_speed = s.abs_speed, out.depth = s.depth;
    return;
  }
  const auto hi = std::upper_bound(samples_.begin(), samples_.end(), t,
                                   [](double v, const FlowSample& s) { return v < s.t; });
  const FlowSample& b = *hi;
  const FlowSample& a = *(hi - 1);
  const double w = (t - a.t) / (b.t - a.t);
  blend(a.speed, b.speed, w, out.speed);
  blend(a.abs_speed, b.abs_speed, w, out.abs_speed);
  blend(a.depth, b.depth, w, out.depth);
}

FlowSample time_average(const FlowRecord& record, double t0, double t1) {
  if (!(t1 > t0)) throw std::invalid_argument("time average: need t1 > t0");
  std::vector<double> times{t0};
  for (const FlowSample& s : record.samples()) {
    if (s.t > t0 && s.t < t1) times.push_back(s.t);
  }
  times.push_back(t1);
  FlowSample avg, a, b;
  record.at(t0, a);
  avg.speed.assign(a.speed.size(), 0.0);
  avg.abs_speed.assign(a.abs_speed.size(), 0.0);
  avg.depth.assign(a.depth.size(), 0.0);
  for (std::size_t k = 1; k < times.size(); ++k) {
    record.at(times[k], b);
    const double w = 0.5 * (times[k] - times[k - 1]) / (t1 - t0);
    for (std::size_t f = 0; f < avg.speed.size(); ++f) {
      avg.speed[f] += w * (a.speed[f] + b.speed[f]);
      avg.abs_speed[f] += w * (a.abs_speed[f] + b.abs_speed[f]);
    }
    for (std::size_t i = 0; i < avg.depth.size(); ++i) avg.depth[i] += w * (a.depth[i] + b.depth[i]);
    std::swap(a, b);
  }
  avg.t = 0.5 * (t0 + t1);
  return avg;
}

}  // namespace grainscale::continuum::closure
