#pragma once
// Averages over several snapshots. A time window is one Moments summed with Moments::add and then
// Moments::average(). A phase average keeps one such sum per phase bin: the caller passes each
// snapshot's phase in the motion cycle (in cycles; only its fractional part counts, so 0.25 and 3.25
// are the same phase), and snapshots at the same phase of different cycles are averaged together.
#include <vector>

#include "coarsegrain/moments.hpp"

namespace grainscale::cg {

class PhaseAverage {
 public:
  /// `bins` equal bins over one cycle, bin b covering phases [b / bins, (b + 1) / bins).
  explicit PhaseAverage(int bins);

  int bins() const { return static_cast<int>(sums_.size()); }
  /// The bin of a phase (any finite value; the fractional part is used). std::invalid_argument for
  /// a non-finite phase.
  int bin_of(double phase) const;
  void add(double phase, const Moments& m);
  /// Number of snapshots in bin b so far.
  int count(int b) const { return sums_[static_cast<std::size_t>(b)].snapshots; }
  /// The averaged moments of bin b (snapshots == 0 if nothing fell into it).
  Moments average(int b) const;
  /// Centre of bin b, in cycles.
  double centre(int b) const { return (b + 0.5) / bins(); }

 private:
  std::vector<Moments> sums_;
};

}  // namespace grainscale::cg
