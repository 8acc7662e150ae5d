#include "continuum/term_registry.hpp"

#include "continuum/terms/advection.hpp"
#include "continuum/terms/background_diffusion.hpp"
#include "continuum/terms/clustering_diffusion.hpp"
#include "continuum/terms/concentration_segregation.hpp"
#include "continuum/terms/lever_arm.hpp"
#include "continuum/terms/pause_creep.hpp"
#include "continuum/terms/segregation.hpp"
#include "continuum/terms/shear_diffusion.hpp"
#include "continuum/terms/surface_drift.hpp"
#include "continuum/terms/wall_mobility.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

namespace {

/// Read every parameter of `term` from `m` (admissible range checked), then reject unknown keys.
std::unique_ptr<FluxTerm> with_parameters(std::unique_ptr<FluxTerm> term, YamlMap& m) {
  for (const Parameter& p : term->parameters().all()) {
    if (p.optional && !m.has(p.name)) continue;
    term->parameters().set(p.name, m.number(p.name, Range::closed(p.valid_lo, p.valid_hi)));
  }
  m.finish();
  return term;
}

Limiter limiter(YamlMap& m) { return limiter_from_name(m.choice_or("limiter", "van_leer", limiter_names())); }

}  // namespace

const std::vector<TermEntry>& term_registry() {
  // One line per effect. The constructor's values are placeholders; the YAML sets every parameter.
  static const std::vector<TermEntry> entries{
      {"advection", "∇·(u c), MUSCL upwind",
       [](YamlMap& m) { return with_parameters(std::make_unique<Advection>(limiter(m)), m); }},
      {"segregation", "∂z[S γ̇ c(1−c)], Engquist–Osher + MUSCL",
       [](YamlMap& m) { return with_parameters(std::make_unique<Segregation>(0.0, limiter(m)), m); }},
      {"shear_diffusion", "∇·(C γ̇ d² ∇c)",
       [](YamlMap& m) { return with_parameters(std::make_unique<ShearDiffusion>(0.0, 1e-3), m); }},
      {"background_diffusion", "∇·(D₀ ∇c)",
       [](YamlMap& m) { return with_parameters(std::make_unique<BackgroundDiffusion>(0.0), m); }},
      // Candidate effects of `grainscale loop` (docs/loop.md), with the parameters the loop fits.
      {"lever_arm", "cycle-mean lean of g_eff off the rotation axis (Euler and centrifugal), drift −S γ̇ a(x, z)",
       [](YamlMap& m) { return with_parameters(std::make_unique<LeverArm>(limiter(m)), m); }, {"S"}},
      {"surface_drift", "surface-layer drift of floating chaff to the ends, U sin(π(x/L − ½))",
       [](YamlMap& m) { return with_parameters(std::make_unique<SurfaceDrift>(limiter(m)), m); }, {"U"}},
      {"concentration_segregation", "∂z[S_c γ̇ c(1−c)²]: dilute chaff rises faster",
       [](YamlMap& m) { return with_parameters(std::make_unique<ConcentrationSegregation>(limiter(m)), m); }, {"S"}},
      {"clustering_diffusion", "∇·(C_c γ̇ d² c ∇c)",
       [](YamlMap& m) { return with_parameters(std::make_unique<ClusteringDiffusion>(), m); }, {"C"}},
      {"wall_mobility", "upward drift W exp(−wall distance / ℓ) at the end walls",
       [](YamlMap& m) { return with_parameters(std::make_unique<WallMobility>(limiter(m)), m); }, {"W"}},
      {"pause_creep", "rise f_p V during the motion's pauses, independent of γ̇",
       [](YamlMap& m) { return with_parameters(std::make_unique<PauseCreep>(limiter(m)), m); }, {"V"}},
  };
  return entries;
}

std::vector<std::string> term_names() {
  std::vector<std::string> names;
  for (const auto& e : term_registry()) names.push_back(e.name);
  return names;
}

std::unique_ptr<FluxTerm> make_term(const std::string& name, YamlMap& params) {
  for (const auto& e : term_registry()) {
    if (e.name == name) return e.make(params);
  }
  std::string list;
  for (const auto& n : term_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError(params.file() + ": unknown continuum term '" + name + "'; choose from: " + list);
}

}  // namespace grainscale::continuum
