#pragma once
// The library of candidate effects that `grainscale loop` tries on a fitted model (docs/loop.md):
// every flux term registered with candidate parameters in continuum/term_registry.cpp (adding one
// is a term file and its registration line), plus the observation operator's visible depth
// (a mis-specified observation operator: coverage = 1 − exp(−κ ∫ c dz) over the wrong top layer).
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "continuum/model.hpp"
#include "continuum/observation.hpp"
#include "studies/loop_motion.hpp"

namespace grainscale::studies {

struct Candidate {
  std::string name, summary;
  bool term = true;                  // false: changes the observation operator, adds no term
  std::vector<std::string> fitted;   // qualified parameter names ("surface_drift.U", "observation.delta")
  YAML::Node settings;               // set (not fitted) parameters given by the user for the term
};

/// Every candidate: the registry's candidate terms, then "observation_depth".
std::vector<Candidate> candidate_library();
std::vector<std::string> candidate_names();

/// The term's YAML: the user's settings, with a placeholder 0 for each fitted parameter they leave
/// out (the registry's fitted parameters are required keys of their terms).
YAML::Node term_node(const Candidate& c);

/// Add the candidate to a model built from the base settings (the term with its set parameters
/// from `settings`, else from `motion` (omega2, alpha2, axis_x, axis_z, pause_fraction) when given, else
/// its defaults; fitted parameters start at the geometric mean of their prior range unless set).
/// The observation candidate changes nothing here (its parameter is already in `observation`).
void add_candidate(const Candidate& c, continuum::Model& model, const MotionFacts* motion, const std::string& source);

}  // namespace grainscale::studies
