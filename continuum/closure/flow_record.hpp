#pragma once
// The closure's state sampled in time, for the chaff model to read between the samples: surface
// speed u_s at the faces, its magnitude (kept apart so that a cycle average can hold ⟨u_s⟩ and
// ⟨|u_s|⟩, see cycle_average below) and the depth h at the cells. Linear interpolation in time.
#include <vector>

#include "continuum/closure/shallow_granular_flow.hpp"

namespace grainscale::continuum::closure {

struct FlowSample {
  double t = 0;
  std::vector<double> speed;      // u_s at the nx + 1 faces [m/s]
  std::vector<double> abs_speed;  // |u_s| at the faces [m/s] (for γ̇)
  std::vector<double> depth;      // h at the nx cells [m]
};

FlowSample sample_of(const ShallowGranularFlow& flow);

class FlowRecord {
 public:
  FlowRecord(double length, int nx) : length_(length), nx_(nx) {}
  double length() const { return length_; }
  int nx() const { return nx_; }
  /// Times must increase.
  void append(FlowSample s);
  /// Drop every sample before the last (the next chunk starts from it).
  void keep_last();
  void clear() { samples_.clear(); }
  const std::vector<FlowSample>& samples() const { return samples_; }
  bool empty() const { return samples_.empty(); }
  /// Linear interpolation in time (clamped to the recorded span) into `out` (sized on first use).
  void at(double t, FlowSample& out) const;

 private:
  double length_;
  int nx_;
  std::vector<FlowSample> samples_;
};

/// Time average over [t0, t1] (trapezoidal over the samples, interpolated at the ends):
/// ⟨u_s⟩, ⟨|u_s|⟩ and ⟨h⟩. With a periodic motion and [t0, t1] a whole number of periods this is the
/// Eulerian cycle average the slow-time model runs on (docs/hold_prediction.md, "Days of motion").
FlowSample time_average(const FlowRecord& record, double t0, double t1);

}  // namespace grainscale::continuum::closure
