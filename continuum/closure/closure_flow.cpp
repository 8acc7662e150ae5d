#include "continuum/closure/closure_flow.hpp"

#include <algorithm>
#include <cmath>

#include "dem/input_error.hpp"

namespace grainscale::continuum::closure {

ClosureFlow::ClosureFlow(std::shared_ptr<const FlowRecord> record, double layer_depth,
                         std::function<double(double)> grid_surface, bool moving)
    : record_(std::move(record)), ell_(layer_depth), surface_(std::move(grid_surface)), moving_(moving) {
  if (!record_) throw InputError("closure flow: no flow record");
  if (!(ell_ > 0)) throw InputError("closure flow: the flowing-layer depth must be positive");
  if (!moving_ && !surface_) throw InputError("closure flow: a frozen surface needs the grid's surface");
}

void ClosureFlow::refresh(double t) const {
  // The record may be refilled between chunks: key the cache on its contents as well as on t.
  const FlowSample* data = record_->samples().empty() ? nullptr : record_->samples().data();
  if (cached_ && t == cache_t_ && data == cache_of_ && record_->samples().size() == cache_count_) return;
  record_->at(t, cache_);
  cache_t_ = t, cache_of_ = data, cache_count_ = record_->samples().size(), cached_ = true;
}

double ClosureFlow::face_value(const std::vector<double>& v, double x) const {
  const double dx = record_->length() / record_->nx();
  const double s = std::clamp(x / dx, 0.0, static_cast<double>(record_->nx()));
  const int f = std::min(static_cast<int>(s), record_->nx() - 1);
  const double w = s - f;
  return (1 - w) * v[f] + w * v[f + 1];
}

double ClosureFlow::surface_height(double x, double t) const {
  refresh(t);
  const int n = record_->nx();
  const double dx = record_->length() / n;
  const double s = std::clamp(x / dx - 0.5, 0.0, static_cast<double>(n - 1));
  const int i = std::min(static_cast<int>(s), n - 2);
  const double w = s - i;
  return (1 - w) * cache_.depth[i] + w * cache_.depth[i + 1];
}

double ClosureFlow::surface_speed(double x, double t) const {
  refresh(t);
  return face_value(cache_.speed, x);
}

double ClosureFlow::column_depth(double x, double t) const { return moving_ ? surface_height(x, t) : surface_(x); }

double ClosureFlow::stream_function(double x, double z, double t) const {
  refresh(t);
  const double us = face_value(cache_.speed, x);
  if (us == 0 || !std::isfinite(ell_)) return 0;
  const double H = column_depth(x, t);
  if (!(H > 0)) return 0;
  const double zc = std::clamp(z, 0.0, H);
  const double raw = us * ell_ * (std::exp(-(H - zc) / ell_) - std::exp(-H / ell_));  // (P1)
  if (moving_) return raw;
  const double q = -us * ell_ * std::expm1(-H / ell_);
  return raw - zc / H * q;
}

double ClosureFlow::shear_rate(double x, double z, double t) const {
  refresh(t);
  if (!std::isfinite(ell_)) return 0;
  const double us = face_value(cache_.abs_speed, x);
  if (us == 0) return 0;
  const double H = column_depth(x, t);
  return us * std::exp(-std::max(H - z, 0.0) / ell_) / ell_;  // (P2)
}

}  // namespace grainscale::continuum::closure
