#include "studies/trial_variants.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>

#include "continuum/observation.hpp"
#include "continuum/term_registry.hpp"
#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"
#include "studies/loop_candidates.hpp"

namespace grainscale::studies {

namespace {

std::string g(double v, int digits = 3) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string at(const std::string& file, const std::string& key, const YAML::Node& n = YAML::Node()) {
  return file + (n && n.Mark().line >= 0 ? ":" + std::to_string(n.Mark().line + 1) : std::string()) + ": key '" + key + "'";
}

/// A number (yaml-cpp reads .nan and .inf) or an InputError naming file and key.
double number_at(const YAML::Node& n, const std::string& file, const std::string& key) {
  if (!n || !n.IsScalar()) throw InputError(at(file, key, n) + " is missing or not a number");
  try {
    return n.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(at(file, key, n) + ": '" + n.Scalar() + "' is not a number");
  }
}

/// The qualified parameters of a loop model entry ({name: {value, standard_error}}).
void read_parameters(const YAML::Node& node, const std::string& file, const std::string& key, TrialVariant& v) {
  const YAML::Node p = node["parameters"];
  if (!p || !p.IsMap()) throw InputError(at(file, key + ".parameters", node) + " is missing (not a loop.yaml?)");
  for (const auto& kv : p) {
    const std::string name = kv.first.as<std::string>();
    v.parameters.emplace_back(name, number_at(kv.second["value"], file, key + ".parameters." + name + ".value"));
    v.errors.push_back(kv.second["standard_error"]
                           ? number_at(kv.second["standard_error"], file, key + ".parameters." + name + ".standard_error")
                           : NAN);
  }
}

const Candidate* find_candidate(const std::vector<Candidate>& lib, const std::string& name) {
  for (const auto& c : lib) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

}  // namespace

std::vector<std::string> variant_effect_names() { return candidate_names(); }

LoopVariants variants_from_loop(const std::string& file, double max_delta_bic, bool constrained_only) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw InputError(file + ": cannot open file (a loop.yaml written by `grainscale loop`)");
  } catch (const YAML::Exception& e) {
    throw InputError(file + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  if (!root.IsMap() || !root["base"] || !root["candidates"] || !root["candidates"].IsSequence()) {
    throw InputError(file + ": not a loop.yaml of `grainscale loop` (keys 'base' and 'candidates' needed)");
  }
  LoopVariants out;
  out.chosen = root["chosen"] ? root["chosen"].as<std::string>() : "none";
  out.reason = root["reason"] ? root["reason"].as<std::string>() : "";
  const auto lib = candidate_library();

  // Every model the loop fitted: the base and each candidate that fitted.
  std::vector<TrialVariant> all;
  TrialVariant base;
  base.name = "base";
  base.file = file;
  base.key = "base";
  read_parameters(root["base"], file, "base", base);
  const double base_bic = number_at(root["base"]["bic"], file, "base.bic");
  std::vector<double> bic = {base_bic};
  std::vector<bool> constrained = {true};
  all.push_back(base);
  const YAML::Node cands = root["candidates"];
  for (std::size_t i = 0; i < cands.size(); ++i) {
    const std::string key = "candidates[" + std::to_string(i) + "]";
    const YAML::Node c = cands[i];
    TrialVariant v;
    v.name = c["name"] ? c["name"].as<std::string>() : "";
    v.effect = v.name;
    v.file = file;
    v.key = key;
    const Candidate* cand = find_candidate(lib, v.name);
    if (!cand) throw InputError(at(file, key + ".name", c) + ": unknown candidate '" + v.name + "'");
    if (c["ok"] && !c["ok"].as<bool>()) {
      out.excluded.push_back({v.name, "its fit failed"});
      continue;
    }
    read_parameters(c, file, key, v);
    const double b = number_at(c["bic"], file, key + ".bic");
    if (!std::isfinite(b)) {
      out.excluded.push_back({v.name, "no BIC"});
      continue;
    }
    bool ok = true;
    for (std::size_t j = 0; j < v.parameters.size(); ++j) {
      for (const auto& q : cand->fitted) {
        if (q == v.parameters[j].first && !(std::abs(v.errors[j]) < std::abs(v.parameters[j].second))) ok = false;
      }
    }
    all.push_back(v);
    bic.push_back(b);
    constrained.push_back(ok);
  }
  double best = bic[0];
  for (double b : bic) best = std::min(best, b);
  for (std::size_t k = 0; k < all.size(); ++k) {
    all[k].delta_bic = bic[k] - best;
    all[k].origin = "`grainscale loop` " + std::string(k == 0 ? "base fit" : "candidate") + ", BIC " + g(bic[k], 4) +
                    " (" + g(all[k].delta_bic, 3) + " above the best)";
  }
  // The loop's chosen model (the base, or the base plus the added effect) always; the others within
  // the threshold. Ordered by BIC, the most plausible first.
  std::size_t chosen = 0;
  for (std::size_t k = 1; k < all.size(); ++k) {
    if (all[k].name == out.chosen) chosen = k;
  }
  all[chosen].origin += "; the loop's chosen model";
  for (std::size_t k = 0; k < all.size(); ++k) {
    if (k == chosen) {
      out.variants.push_back(all[k]);
    } else if (!(all[k].delta_bic < max_delta_bic)) {
      out.excluded.push_back({all[k].name, "BIC " + g(all[k].delta_bic, 3) + " above the best (not below " +
                                               g(max_delta_bic, 3) + ")"});
    } else if (constrained_only && !constrained[k]) {
      out.excluded.push_back({all[k].name, "strength not constrained (standard error not below the value)"});
    } else {
      out.variants.push_back(all[k]);
    }
  }
  std::stable_sort(out.variants.begin(), out.variants.end(),
                   [](const TrialVariant& a, const TrialVariant& b) { return a.delta_bic < b.delta_bic; });
  return out;
}

void apply_variant(const TrialVariant& v, HoldSettings& s, const MotionFacts& facts, double& kappa, double& delta) {
  const std::string where = v.file + ": key '" + v.key + "'";
  const auto lib = candidate_library();
  if (!v.effect.empty()) {
    const Candidate* cand = find_candidate(lib, v.effect);
    if (!cand) {
      std::string names;
      for (const auto& n : candidate_names()) names += (names.empty() ? "" : ", ") + n;
      throw InputError(where + ": unknown effect '" + v.effect + "'; choose from: " + names);
    }
    for (const auto& t : s.terms) {
      if (t.first == v.effect) throw InputError(where + ": the base model already has '" + v.effect + "'");
    }
    for (const auto& q : cand->fitted) {
      bool given = false;
      for (const auto& p : v.parameters) given = given || p.first == q;
      if (!given) throw InputError(where + ": effect '" + v.effect + "' needs its strength '" + q + "'");
    }
    if (cand->term) {
      // The motion-derived parameters the term has, from this trial's motion.
      YAML::Node node(YAML::NodeType::Map);
      const std::pair<const char*, double> from_motion[] = {{"omega2", facts.omega2_mean},
                                                            {"alpha2", facts.alpha2_mean},
                                                            {"axis_x", facts.axis_x},
                                                            {"axis_z", facts.axis_z},
                                                            {"pause_fraction", facts.pause_fraction}};
      YAML::Node probe_node(YAML::NodeType::Map);
      for (const auto& q : cand->fitted) probe_node[q.substr(q.find('.') + 1)] = 0.0;
      YamlMap probe(probe_node, v.file, v.key);
      const auto term = continuum::make_term(v.effect, probe);
      for (const auto& [key, value] : from_motion) {
        if (term->parameters().has(key)) node[key] = value;
      }
      s.terms.emplace_back(v.effect, node);
    }
  }
  for (const auto& [q, value] : v.parameters) {
    const auto dot = q.find('.');
    const std::string term = q.substr(0, dot), p = dot == std::string::npos ? "" : q.substr(dot + 1);
    if (term == "observation") {
      if (p == "kappa") {
        kappa = value;
      } else if (p == "delta") {
        delta = value;
      } else {
        throw InputError(where + ": unknown parameter '" + q + "' (observation has kappa and delta)");
      }
      continue;
    }
    bool found = false;
    for (auto& t : s.terms) {
      if (t.first != term) continue;
      t.second[p] = value;
      found = true;
    }
    if (!found || p.empty()) {
      std::string names;
      for (const auto& t : s.terms) names += (names.empty() ? "" : ", ") + t.first;
      throw InputError(where + ": parameter '" + q + "' names no term of the model (terms: " + names +
                       ", observation)");
    }
  }
  // Every term built once: unknown parameter names and values out of range fail here.
  for (const auto& [name, node] : s.terms) {
    YamlMap m(YAML::Clone(node), v.file, name);
    try {
      (void)continuum::make_term(name, m);
    } catch (const InputError& e) {
      throw InputError(where + ": variant '" + v.name + "': " + e.what());
    }
  }
  try {
    (void)continuum::SurfaceCoverage(kappa, delta);
  } catch (const InputError& e) {
    throw InputError(where + ": variant '" + v.name + "': " + e.what());
  }
}

}  // namespace grainscale::studies
