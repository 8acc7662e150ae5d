#pragma once
// The model variants a `trial_planning` study tries to tell apart (docs/studies.md): the base chaff
// model and candidate effects of `grainscale loop` (docs/loop.md), each with its fitted strength.
// They come from a loop.yaml the loop wrote (the loop's chosen model, plus every model whose BIC is
// within `max_delta_bic` of the best model's and, if asked, whose fitted strength is constrained:
// standard error below the value; ordered by BIC) and/or are listed in the study file. A variant sets parameters by
// qualified name ("segregation.S", "surface_drift.U", "observation.kappa") and adds at most one
// candidate effect (a term of continuum/term_registry.cpp with candidate parameters, or the loop's
// observation_depth). The effect's motion-derived parameters (lever_arm: ⟨ω²⟩ and the axis;
// pause_creep: the pause fraction) come from each trial's own motion, not the loop's experiment.
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "studies/hold_settings.hpp"
#include "studies/loop_motion.hpp"

namespace grainscale::studies {

struct TrialVariant {
  std::string name;    // unique within the study
  std::string effect;  // "" (base model) or a candidate name
  std::vector<std::pair<std::string, double>> parameters;  // qualified name -> value
  std::vector<double> errors;                              // standard errors (NaN: not known), as parameters
  std::string origin;                                      // e.g. "loop.yaml: candidate, dBIC -18.9 from the base"
  double delta_bic = std::numeric_limits<double>::quiet_NaN();  // BIC above the best loop model (NaN: not from a loop)
  std::string file, key;                                   // where it was read, for messages
};

/// A loop candidate left out, and why.
struct ExcludedVariant {
  std::string name, reason;
};

struct LoopVariants {
  std::vector<TrialVariant> variants;  // by BIC, the most plausible first (the loop's choice always in)
  std::vector<ExcludedVariant> excluded;
  std::string chosen, reason;          // the loop's decision
};

/// Reads loop.yaml (`grainscale loop`'s output). InputError naming the file and key if a needed key
/// is missing or malformed.
LoopVariants variants_from_loop(const std::string& loop_yaml, double max_delta_bic, bool constrained_only);

/// Every candidate effect a variant may name.
std::vector<std::string> variant_effect_names();

/// Applies the variant to hold settings whose terms are private copies: the effect's term added
/// (its motion-derived parameters from `facts`), parameters set; the observation's κ and δ returned
/// through `kappa`, `delta` when the variant sets them. Every term is built once to check names and
/// ranges: InputError naming the variant's file and key (unknown effect or term, an effect already
/// in the model, a missing strength, a value out of range).
void apply_variant(const TrialVariant& v, HoldSettings& s, const MotionFacts& facts, double& kappa, double& delta);

}  // namespace grainscale::studies
