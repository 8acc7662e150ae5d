#pragma once
// Particle scale-up: running a material with particles s >= 1 times their true size (the source report
// ran its platform test at s = 2 because s = 1 took four weeks for 400 s). The rules, their sources and
// their limits are in docs/scaling.md; in short:
//
//   shape             every sphere's centre and radius times s          (geometric similarity)
//   density, G, nu    unchanged                                          (Bierwisch et al. 2009)
//   restitution, mu   unchanged (dimensionless)                          (Bierwisch et al. 2009; Radl et al. 2011)
//   rolling friction  `keep` (default): mu_r unchanged, so the lever arm mu_r R grows with R
//                     `inverse`: lever arm fixed in metres, mu_r(s) = mu_r(s0) s0 / s
//   time step         follows the sizes: the Rayleigh time is proportional to R (dem/time_step.hpp)
//
// With these rules a Hertz contact at the same impact speed lasts s times longer (t_c ~ (m*^2 /
// (R* E*^2 v))^(1/5) ~ s), stresses from gravity grow with s, and every dimensionless group of a
// quasi-static pile stays except the ratios of container to particle size. Those last ones are what
// breaks a scaled run, so a scenario can be checked for containers and openings that are only a few
// scaled particles wide (narrow_passage_warnings).
#include <string>
#include <vector>

#include "dem/material.hpp"
#include "dem/scenario.hpp"
#include "dem/shape.hpp"

namespace grainscale::dem {

enum class RollingFrictionRule { keep, inverse };

const std::vector<std::string>& rolling_friction_rule_names();  // "keep", "inverse"
RollingFrictionRule rolling_friction_rule_from_name(const std::string& name);
std::string rolling_friction_rule_name(RollingFrictionRule r);

struct ScalingRules {
  double factor = 1;         // s: particle size / true size, >= 1
  double calibrated_at = 1;  // the scale factor at which the materials' values were obtained
  RollingFrictionRule rolling = RollingFrictionRule::keep;
};

/// Throws InputError unless factor and calibrated_at are finite and >= 1.
void check_rules(const ScalingRules& rules);

/// A true-size shape made s times larger (centres and radii; measured sizes too).
Shape scale_shape(const Shape& true_size, double s);

/// Material and pair properties at the scaled size. Materials are unchanged; a pair keeps its
/// restitution and sliding friction, and its rolling friction follows `rules.rolling`.
Material scale_material(const Material& m, const ScalingRules& rules);
PairProperties scale_pair(const PairProperties& p, const ScalingRules& rules);
MaterialTable scale_materials(const MaterialTable& t, const ScalingRules& rules);

// --- Containers and openings only a few particles wide ------------------------------------------

/// A width the grain must pass through (an opening, e.g. the AOR pipe's bore) or live in (a
/// container: box, tray, cylinder), found from a scenario's walls.
struct Passage {
  std::string wall;   // wall name
  std::string what;   // e.g. "pipe bore", "tray", "box compartment"
  double width = 0;   // m, the narrowest horizontal width
  bool opening = false;
};

/// Narrowest widths, as multiples of the particle size, below which a run warns. Openings: clogging
/// and the Beverloo empty annulus (about 1.5 d at each side) make flow through fewer than about five or
/// six particle sizes depend on the size itself (Beverloo et al. 1961; Zuriguel et al. 2005). Containers:
/// the packing is disturbed within a few particle sizes of a wall, so below about ten particle sizes
/// across, wall layers fill much of the container. Sources and discussion: docs/scaling.md.
struct NarrowLimits {
  double opening = 6;
  double container = 10;
};

/// Passages of a loaded scenario's walls. The wall type (and box compartments) are read back from the
/// scenario file; widths come from the wall keys. Planes bound nothing; an STL mesh counts as a
/// container as wide as its narrowest horizontal extent (an approximation: say so in a warning).
std::vector<Passage> scenario_passages(const Scenario& s);

/// Largest particle size of the scenario's batches (already scaled): a clump's longest bounding
/// dimension, a sphere's largest diameter d (1 + spread). Metres; 0 without particles.
double largest_particle_size(const Scenario& s);

/// One line per passage narrower than its limit times `particle_size`; empty when all are wide enough.
std::vector<std::string> narrow_passage_warnings(const std::vector<Passage>& passages, double particle_size,
                                                 double scale_factor, const NarrowLimits& limits = {});

/// The check for a whole scenario (what a run logs as warnings at set-up).
std::vector<std::string> narrow_passage_warnings(const Scenario& s, const NarrowLimits& limits = {});

}  // namespace grainscale::dem
