#include "studies/trial_plan_settings.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"
#include "studies/loop_motion.hpp"
#include "studies/numeric_csv.hpp"

namespace grainscale::studies {

namespace {

constexpr std::size_t kMaxDesigns = 10000;

struct Grid {
  std::vector<std::string> motions;
  std::vector<double> lengths, fills, amplitudes, periods;
};

/// One grid of the sweep (a mapping of axes -> lists); an absent axis keeps the base's value.
Grid read_grid(YamlMap& m, const TrialPlanSettings& s) {
  std::vector<std::string> names;
  for (const auto& mo : s.motions) names.push_back(mo.name);
  Grid gr;
  auto axis = [&](const std::string& key, Range r) {
    std::vector<double> v = m.numbers_or_empty(key, 0, 1000, r);
    if (m.has(key) && v.empty()) throw InputError(m.where(key) + ": an empty axis (give at least one value, or leave the key out)");
    return v;
  };
  gr.motions = m.choices_or_empty("motion", names);
  if (m.has("motion") && gr.motions.empty()) {
    throw InputError(m.where("motion") + ": an empty axis (give at least one motion, or leave the key out)");
  }
  gr.lengths = axis("length", Range{0, 1e4, true, false});
  gr.fills = axis("fill_height", Range{0, s.base.depth, true, false});
  gr.amplitudes = axis("amplitude_deg", Range{0, 90, true, true});
  gr.periods = axis("period", Range{0, 1e6, true, false});
  m.finish();
  return gr;
}

TrialMotion read_motion(YamlMap& m, const std::string& name) {
  TrialMotion t;
  t.name = name;
  t.file = m.file();
  t.key = m.path() + ".motion";
  (void)m.map("motion");  // must be a mapping; checked fully when built
  t.block = YAML::Clone(YAML::LoadFile(m.file())["motions"][name]["motion"]);
  t.direction = m.choice_or("direction", "longitudinal", {"longitudinal", "transverse"});
  const std::vector<double> pivot = m.numbers_or_empty("pivot", 2, 2);
  if (!pivot.empty()) t.pivot_x = pivot[0], t.pivot_z = pivot[1];
  t.pivot_from_centre = m.choice_or("pivot_from", "wall", {"wall", "centre"}) == "centre";
  m.finish();
  return t;
}

/// Measurement σ of the centre and the ends from a t_s,x_m,coverage,sigma file: the centre is the row
/// nearest the middle of the rows' x range, the ends the smaller σ of the two outermost rows (the
/// trustworthy end; the report's left end is a lighting artefact).
void sigma_from_csv(const std::string& file, const std::string& where, double& centre, double& ends) {
  const NumericCsv csv = NumericCsv::load(file);
  const std::vector<double> x = csv.column("x_m"), sigma = csv.column("sigma");
  if (x.size() < 3) throw InputError(where + ": " + file + " needs at least 3 rows (two ends and a centre)");
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  const double mid = 0.5 * (*lo + *hi);
  std::size_t c = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i] - mid) < std::abs(x[c] - mid)) c = i;
  }
  centre = sigma[c];
  ends = std::min(sigma[lo - x.begin()], sigma[hi - x.begin()]);
  if (!(centre > 0) || !(ends > 0)) throw InputError(where + ": " + file + ": sigma must be > 0");
}

}  // namespace

const TrialMotion& motion_of(const TrialPlanSettings& s, const TrialDesign& d) {
  for (const auto& m : s.motions) {
    if (m.name == d.motion) return m;
  }
  throw std::logic_error("trial design names an unknown motion " + d.motion);
}

TrialPlanSettings load_trial_plan_settings(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  const YAML::Node raw = YAML::LoadFile(file);
  TrialPlanSettings s;
  s.source_file = file;
  s.inputs.push_back(file);
  (void)root.choice("kind", {"trial_planning"});
  s.name = root.string("name");
  if (s.name.empty() || s.name.find('/') != std::string::npos) throw InputError(root.where("name") + ": a word without '/'");
  s.title = root.string_or("title", "Trial planning: " + s.name);
  s.description = root.string_or("description", "");
  s.base_file = resolve_beside(file, root.string("base"));
  s.inputs.push_back(s.base_file);
  s.base = load_hold_settings(s.base_file);

  // Named motions: the base file's own, then the study's.
  {
    TrialMotion base;
    base.name = "base";
    base.file = s.base_file;
    base.key = "motion";
    base.block = YAML::Clone(YAML::LoadFile(s.base_file)["motion"]);
    base.direction = s.base.direction;
    base.pivot_x = s.base.pivot_x;
    base.pivot_z = s.base.pivot_z;
    s.motions.push_back(base);
    if (auto ms = root.optional_map("motions")) {
      for (const std::string& n : ms->keys()) {
        if (n == "base") throw InputError(ms->where(n) + ": 'base' is the base file's motion; choose another name");
        YamlMap m = ms->map(n);
        s.motions.push_back(read_motion(m, n));
      }
      ms->finish();
    }
  }

  {
    YamlMap t = root.map("time");
    s.duration = t.number_or("duration", s.base.t_end, Range{0, 1e9, true, false});
    const std::string resolve = t.string_or("resolve", "all");
    if (resolve == "all") {
      s.resolve = 0;
    } else {
      try {
        std::size_t used = 0;
        s.resolve = std::stol(resolve, &used);
        if (used != resolve.size() || s.resolve < 1) throw std::invalid_argument(resolve);
      } catch (const std::exception&) {
        throw InputError(t.where("resolve") + ": 'all' or a number of cycles >= 1");
      }
    }
    s.average_cycles = t.integer_or("average_cycles", 10, 1, 1000000);
    if (s.resolve > 0 && s.average_cycles > s.resolve) {
      throw InputError(t.where("average_cycles") + ": must not exceed the resolved cycles (" + std::to_string(s.resolve) + ")");
    }
    t.finish();
  }
  {
    YamlMap o = root.map("observation");
    s.kappa = o.number("kappa", Range{0, 1e6, true, false});
    s.delta = o.number("delta", Range{1e-6, 1.0});
    s.end_length = o.number_or("end_length", 0.1, Range{0, 1e3, true, false});
    o.finish();
  }

  // The sweep: one grid, or a list of grids.
  {
    if (!raw["sweep"]) throw InputError(root.where("sweep") + ": missing (one grid of axes, or a list of grids)");
    std::vector<Grid> grids;
    if (raw["sweep"].IsSequence()) {
      for (YamlMap& m : root.list_of_maps("sweep")) grids.push_back(read_grid(m, s));
      if (grids.empty()) throw InputError(root.where("sweep") + ": an empty list of grids");
    } else {
      YamlMap m = root.map("sweep");
      grids.push_back(read_grid(m, s));
    }
    std::set<std::tuple<std::string, double, double, double, double>> seen;
    std::set<std::string> varying;
    for (const Grid& gr : grids) {
      const auto motions = gr.motions.empty() ? std::vector<std::string>{"base"} : gr.motions;
      const auto lengths = gr.lengths.empty() ? std::vector<double>{s.base.length} : gr.lengths;
      const auto fills = gr.fills.empty() ? std::vector<double>{s.base.fill_height} : gr.fills;
      const auto amps = gr.amplitudes.empty() ? std::vector<double>{NAN} : gr.amplitudes;
      const auto pers = gr.periods.empty() ? std::vector<double>{NAN} : gr.periods;
      for (const auto& mo : motions)
        for (double L : lengths)
          for (double f : fills)
            for (double A : amps)
              for (double P : pers) {
                TrialDesign d;
                d.motion = mo;
                d.length = L;
                d.fill_height = f;
                d.amplitude_swept = std::isfinite(A);
                d.period_swept = std::isfinite(P);
                const TrialMotion& m = motion_of(s, d);
                const YAML::Node block = rescaled_motion(m, d.amplitude_swept, A, d.period_swept, P,
                                                         file + ": key 'sweep'");
                motion_amplitude_period(m, block, d.amplitude_deg, d.period);
                d.amplitude_deg = std::round(d.amplitude_deg * 1e6) / 1e6;  // sampled over a cycle: ~1e-8 off
                if (d.amplitude_swept) d.amplitude_deg = A;  // the set value (the sampled peak differs by ~1e-3)
                if (d.period_swept) d.period = P;
                const auto key = std::make_tuple(d.motion, d.length, d.fill_height, std::round(d.amplitude_deg * 1e6),
                                                 std::round(d.period * 1e6));
                if (!seen.insert(key).second) continue;
                d.index = static_cast<int>(s.designs.size());
                s.designs.push_back(d);
                if (s.designs.size() > kMaxDesigns) {
                  throw InputError(root.where("sweep") + ": more than " + std::to_string(kMaxDesigns) + " designs");
                }
              }
    }
    auto varies = [&](auto get) {
      for (const auto& d : s.designs) {
        if (get(d) != get(s.designs.front())) return true;
      }
      return false;
    };
    if (varies([](const TrialDesign& d) { return d.motion; })) s.swept.push_back("motion");
    if (varies([](const TrialDesign& d) { return d.length; })) s.swept.push_back("length");
    if (varies([](const TrialDesign& d) { return d.fill_height; })) s.swept.push_back("fill_height");
    if (varies([](const TrialDesign& d) { return d.amplitude_deg; })) s.swept.push_back("amplitude_deg");
    if (varies([](const TrialDesign& d) { return d.period; })) s.swept.push_back("period");
  }

  s.heat_map = root.choices_or_empty("heat_map", {"length", "fill_height", "amplitude_deg", "period"});
  if (root.has("heat_map")) {
    if (s.heat_map.size() != 2 || s.heat_map[0] == s.heat_map[1]) {
      throw InputError(root.where("heat_map") + ": two different variables, e.g. [length, amplitude_deg]");
    }
    for (const auto& a : s.heat_map) {
      if (std::find(s.swept.begin(), s.swept.end(), a) == s.swept.end()) {
        throw InputError(root.where("heat_map") + ": '" + a + "' does not vary in the sweep");
      }
    }
  }

  // Variants: from a loop.yaml and/or listed.
  {
    YamlMap v = root.map("variants");
    if (auto l = v.optional_map("loop")) {
      s.loop_file = resolve_beside(file, l->string("file"));
      s.max_delta_bic = l->number_or("max_delta_bic", 10, Range::positive());
      s.constrained_only = l->boolean_or("constrained_only", true);
      l->finish();
      s.inputs.push_back(s.loop_file);
      LoopVariants lv = variants_from_loop(s.loop_file, s.max_delta_bic, s.constrained_only);
      s.variants = lv.variants;
      s.excluded = lv.excluded;
      s.loop_chosen = lv.chosen;
      s.loop_reason = lv.reason;
    }
    if (v.has("list")) {
      std::vector<YamlMap> items = v.list_of_maps("list");
      for (std::size_t i = 0; i < items.size(); ++i) {
        YamlMap& m = items[i];
        TrialVariant t;
        t.file = file;
        t.key = m.path();
        t.name = m.string("name");
        t.effect = m.string_or("effect", "");
        t.origin = m.string_or("origin", "listed in the study file");
        if (auto p = m.optional_map("parameters")) {
          for (const std::string& q : p->keys()) {
            t.parameters.emplace_back(q, p->number(q));
            t.errors.push_back(NAN);
          }
          p->finish();
        }
        m.finish();
        s.variants.push_back(t);
      }
    }
    v.finish();
    if (s.variants.empty()) throw InputError(root.where("variants") + ": no variant (give 'loop' or 'list')");
    std::set<std::string> names;
    for (const auto& t : s.variants) {
      if (!names.insert(t.name).second) {
        throw InputError(t.file + ": key '" + t.key + "': variant name '" + t.name + "' used twice");
      }
      if (t.name.empty() || t.name.find_first_of("/, ") != std::string::npos) {
        throw InputError(t.file + ": key '" + t.key + ".name': a word without '/', ',' or spaces");
      }
    }
  }
  {
    YamlMap d = root.map("discrimination");
    DiscriminationSettings& ds = s.discrimination;
    if (d.has("sigma_from") == d.has("sigma")) {
      throw InputError(d.where("sigma") + ": give exactly one of 'sigma: {centre, ends}' or 'sigma_from: FILE.csv'");
    }
    if (d.has("sigma_from")) {
      const std::string f = resolve_beside(file, d.string("sigma_from"));
      sigma_from_csv(f, d.where("sigma_from"), ds.sigma_centre, ds.sigma_end);
      s.sigma_source = "`sigma` column of " + d.string("sigma_from");
      s.inputs.push_back(f);
    } else {
      YamlMap sg = d.map("sigma");
      ds.sigma_centre = sg.number("centre", Range{0, 1, true, false});
      ds.sigma_end = sg.number("ends", Range{0, 1, true, false});
      sg.finish();
      s.sigma_source = "the study file";
    }
    ds.score = d.choice_or("score", "min", {"min", "mean"});
    ds.top = static_cast<int>(d.integer_or("top", 5, 1, 1000));
    ds.min_separation = d.number_or("min_separation", 2.0, Range::positive());
    d.finish();
  }
  {
    YamlMap o = root.map("output");
    s.output_directory = resolve_beside(file, o.string("directory"));
    o.finish();
  }
  root.finish();

  // Every variant built once on the first design (every design's motion was built above), so a bad
  // variant fails before anything runs.
  const TrialDesign& d0 = s.designs.front();
  for (const auto& v : s.variants) {
    HoldSettings hs = hold_settings_for(s.base, motion_of(s, d0), d0, s.duration, s.resolve, s.average_cycles, s.end_length);
    MotionFacts facts = cycle_facts(*hs.motion);
    facts.axis_x = hs.pivot_x;
    facts.axis_z = hs.pivot_z;
    double kappa = s.kappa, delta = s.delta;
    apply_variant(v, hs, facts, kappa, delta);
  }
  return s;
}

}  // namespace grainscale::studies
