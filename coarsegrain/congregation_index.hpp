#pragma once
// A congregation index: how much more chaff the ends of the container hold than the container as a
// whole (issue 6: "chaff fraction in the outer 100 mm at each end relative to the mean").
//
//   index_end = c_end / c_all,   c = chaff bodies / all bodies (grain and chaff), counted at centres
//
// where c_end is taken over the outer `end_length` at that end and c_all over the whole length.
// A uniform mixture gives 1 at both ends; chaff gathering at the ends gives > 1. `share_end` is the
// report's Figure 11 reading: the fraction of all chaff bodies that lie in the end zone, divided by
// the zone's share of the length (1 for a uniform spread; the report found "more than double the
// percentage of chaff particles ... in the right hand 100mm" compared with the initial spread).
//
// From the top view: coverage_ratio = mean coverage of the two end zones / coverage of a central
// zone of the same length (the report's photographs: about 60 % / 10 % = 6 for wheat).
// `mean` and `spread` summarise the two ends: their mean and half their difference (right - left).
#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/top_view.hpp"

namespace grainscale::cg {

struct CongregationIndex {
  double left = 0, right = 0;              // c_end / c_all
  double mean = 0, spread = 0;             // (left + right) / 2, (right - left) / 2
  double share_left = 0, share_right = 0;  // chaff share in the zone / zone length share
  double coverage_left = 0, coverage_centre = 0, coverage_right = 0, coverage_ratio = 0;
};

/// The index of one snapshot over [x_lo, x_hi] with end zones of `end_length`. NaN parts where a zone
/// holds no bodies (or no occupied pixels). `view` may be null: the coverage entries are then NaN.
CongregationIndex congregation_index(const CgParticles& particles, const SpeciesTable& species, double x_lo, double x_hi,
                                     double end_length, const TopView* view);

}  // namespace grainscale::cg
