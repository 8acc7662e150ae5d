#include "studies/trial_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "dem/atomic_file.hpp"
#include "studies/plot.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string g(double v, int digits = 4) {
  if (!std::isfinite(v)) return "n/a";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string num(double v) {
  if (!std::isfinite(v)) return "nan";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string pct(double v) { return std::isfinite(v) ? g(100 * v, 3) + " %" : "n/a"; }

std::string figure(const std::string& out, const std::string& rel, const std::string& caption) {
  if (!fs::exists(fs::path(out) / rel)) return "*(" + caption + ": not drawn)*\n\n";
  return "![" + caption + "](" + rel + ")\n\n*" + caption + "*\n\n";
}

/// A numeric axis of the sweep.
struct NumericAxis {
  std::string key, label;
  double (*get)(const TrialDesign&);
};

const std::vector<NumericAxis>& numeric_axes() {
  static const std::vector<NumericAxis> axes = {
      {"length", "container length (m)", [](const TrialDesign& d) { return d.length; }},
      {"fill_height", "fill depth (m)", [](const TrialDesign& d) { return d.fill_height; }},
      {"amplitude_deg", "tilt amplitude (deg)", [](const TrialDesign& d) { return d.amplitude_deg; }},
      {"period", "cycle period (s)", [](const TrialDesign& d) { return d.period; }},
  };
  return axes;
}

bool swept(const TrialPlanSettings& s, const std::string& key) {
  return std::find(s.swept.begin(), s.swept.end(), key) != s.swept.end();
}

std::vector<double> values_of(const TrialPlanSettings& s, const NumericAxis& a) {
  std::set<double> v;
  for (const auto& d : s.designs) v.insert(a.get(d));
  return {v.begin(), v.end()};
}

/// Cell edges around sorted values (midpoints; half a gap beyond the ends).
std::vector<double> edges_around(const std::vector<double>& v) {
  std::vector<double> e;
  e.push_back(v[0] - 0.5 * (v[1] - v[0]));
  for (std::size_t i = 0; i + 1 < v.size(); ++i) e.push_back(0.5 * (v[i] + v[i + 1]));
  e.push_back(v.back() + 0.5 * (v.back() - v[v.size() - 2]));
  return e;
}

/// Mean of `value(design)` over the designs with each value of the axis (NaN results skipped).
template <class F>
std::vector<double> mean_by(const TrialPlanSettings& s, const NumericAxis& a, const std::vector<double>& vals, F value) {
  std::vector<double> out;
  for (double x : vals) {
    double sum = 0;
    int n = 0;
    for (const auto& d : s.designs) {
      const double y = value(d.index);
      if (a.get(d) == x && std::isfinite(y)) sum += y, ++n;
    }
    out.push_back(n ? sum / n : NAN);
  }
  return out;
}

/// The motion with the most designs (the first such): the line plots and the heat map show its designs
/// only, so that averages do not mix motions.
std::string main_motion(const TrialPlanSettings& s) {
  std::map<std::string, int> count;
  std::string best;
  for (const auto& d : s.designs) {
    if (++count[d.motion] > count[best]) best = d.motion;
  }
  return best;
}

/// The settings with only the main motion's designs (indices into the results kept).
TrialPlanSettings main_designs(const TrialPlanSettings& s) {
  TrialPlanSettings m = s;
  m.designs.clear();
  const std::string name = main_motion(s);
  for (const auto& d : s.designs) {
    if (d.motion == name) m.designs.push_back(d);
  }
  return m;
}

void write_figures(const TrialPlanSettings& all_designs, const TrialSweepResult& r, const std::vector<TrialScore>& ranked,
                   const std::vector<TrialScore>& recommended, const std::string& out, std::vector<std::string>& warnings) {
  const TrialPlanSettings s = main_designs(all_designs);
  const std::string which = swept(all_designs, "motion") ? " (" + main_motion(all_designs) + ")" : "";
  const std::size_t nv = s.variants.size();
  auto ratio = [&](std::size_t v) { return [&r, v](int d) { return r.cases[d][v].ratio; }; };
  std::map<int, double> score_of;
  for (const auto& t : ranked) score_of[t.design] = t.score;
  auto safe_draw = [&](const auto& plot, const std::string& file) {
    try {
      draw(plot).write_png((fs::path(out) / file).string());
    } catch (const std::exception& e) {
      warnings.push_back(file + " not drawn: " + e.what());
    }
  };
  for (const NumericAxis& a : numeric_axes()) {
    const std::vector<double> vals = values_of(s, a);
    if (vals.size() < 2) continue;
    LinePlot p;
    p.axes.title = "Predicted congregation" + which + " vs " + a.label;
    p.axes.x_label = a.label;
    p.axes.y_label = "end / centre coverage";
    for (std::size_t v = 0; v < nv; ++v) {
      p.series.push_back({s.variants[v].name + " (mean)", vals, mean_by(s, a, vals, ratio(v)), LineStyle::solid, Marker::circle});
    }
    Series all{"designs (" + s.variants[0].name + ")", {}, {}, LineStyle::none, Marker::cross};
    for (const auto& d : s.designs) all.x.push_back(a.get(d)), all.y.push_back(r.cases[d.index][0].ratio);
    p.series.push_back(all);
    safe_draw(p, "congregation_" + a.key + ".png");

    LinePlot q;
    q.axes.title = "How well a trial" + which + " separates the variants vs " + a.label;
    q.axes.x_label = a.label;
    q.axes.y_label = "score (" + s.discrimination.score + " pairwise separation / sigma)";
    q.axes.y_min = 0;
    auto score = [&](int d) { return score_of[d]; };
    std::vector<double> best;
    for (double x : vals) {
      double m = NAN;
      for (const auto& d : s.designs) {
        if (a.get(d) == x) m = std::isfinite(m) ? std::max(m, score_of[d.index]) : score_of[d.index];
      }
      best.push_back(m);
    }
    q.series.push_back({"best", vals, best, LineStyle::solid, Marker::circle});
    q.series.push_back({"mean", vals, mean_by(s, a, vals, score), LineStyle::dashed, Marker::square});
    q.series.push_back({"threshold", {vals.front(), vals.back()},
                        {s.discrimination.min_separation, s.discrimination.min_separation}, LineStyle::dashed});
    safe_draw(q, "discrimination_" + a.key + ".png");
  }
  if (swept(all_designs, "motion")) {
    const TrialPlanSettings& s = all_designs;
    std::vector<std::string> names;
    for (const auto& d : s.designs) {
      if (std::find(names.begin(), names.end(), d.motion) == names.end()) names.push_back(d.motion);
    }
    BarChart b;
    std::string legend;
    for (std::size_t i = 0; i < names.size(); ++i) legend += (i ? ", " : "") + std::to_string(i) + " " + names[i];
    b.axes.title = "Predicted congregation by motion (mean over the other variables)";
    b.axes.x_label = "motion: " + legend;
    b.axes.y_label = "end / centre coverage";
    for (std::size_t i = 0; i <= names.size(); ++i) b.edges.push_back(static_cast<double>(i) - 0.5);
    for (std::size_t v = 0; v < nv; ++v) {
      BarSeries bs{s.variants[v].name, {}};
      for (const auto& n : names) {
        double sum = 0;
        int k = 0;
        for (const auto& d : s.designs) {
          if (d.motion == n && std::isfinite(r.cases[d.index][v].ratio)) sum += r.cases[d.index][v].ratio, ++k;
        }
        bs.values.push_back(k ? sum / k : NAN);
      }
      b.series.push_back(bs);
    }
    safe_draw(b, "congregation_motion.png");
  }
  // Heat map over the first two numeric variables swept with at least two values each.
  std::vector<const NumericAxis*> two;
  for (const NumericAxis& a : numeric_axes()) {
    const bool chosen = std::find(s.heat_map.begin(), s.heat_map.end(), a.key) != s.heat_map.end();
    if (s.heat_map.empty() ? values_of(s, a).size() >= 2 && two.size() < 2 : chosen) two.push_back(&a);
  }
  if (two.size() == 2 && !s.heat_map.empty() && s.heat_map[0] != two[0]->key) std::swap(two[0], two[1]);
  if (two.size() == 2 && values_of(s, *two[0]).size() >= 2 && values_of(s, *two[1]).size() >= 2) {
    const std::vector<double> xv = values_of(s, *two[0]), yv = values_of(s, *two[1]);
    HeatMap h;
    h.axes.title = "Congregation" + which + ", " + s.variants[0].name;
    h.axes.x_label = two[0]->label;
    h.axes.y_label = two[1]->label;
    h.x_edges = edges_around(xv);
    h.y_edges = edges_around(yv);
    h.value_label = "end / centre coverage";
    for (double y : yv) {
      for (double x : xv) {
        double sum = 0;
        int n = 0;
        for (const auto& d : s.designs) {
          const double v = r.cases[d.index][0].ratio;
          if (two[0]->get(d) == x && two[1]->get(d) == y && std::isfinite(v)) sum += v, ++n;
        }
        h.values.push_back(n ? sum / n : NAN);
      }
    }
    safe_draw(h, "congregation_map.png");
  }
  // Coverage along the container of the best trials (the recommended ones, else the best scored).
  const std::vector<TrialScore>& shown = recommended.empty() ? ranked : recommended;
  for (std::size_t k = 0; k < std::min<std::size_t>(3, shown.size()); ++k) {
    const TrialDesign& d = s.designs[shown[k].design];
    LinePlot p;
    p.axes.title = "Trial " + std::to_string(k + 1) + ": " + d.label();
    p.axes.x_label = "x along the container (m)";
    p.axes.y_label = "predicted top-view coverage";
    p.axes.y_min = 0;
    for (std::size_t v = 0; v < nv; ++v) {
      const TrialCaseResult& c = r.cases[d.index][v];
      p.series.push_back({s.variants[v].name, c.x, c.profile, LineStyle::solid, Marker::none, palette(v)});
      const double e = std::min(s.end_length, 0.5 * d.length);
      p.series.push_back({"", {0.5 * e, 0.5 * d.length, d.length - 0.5 * e}, {c.coverage.left, c.coverage.centre, c.coverage.right},
                          LineStyle::none, Marker::circle, palette(v)});
    }
    safe_draw(p, "trial_" + std::to_string(k + 1) + ".png");
  }
}

/// Candidate effects whose drift does not scale with the local shear rate (docs/loop.md's equations):
/// they act even where the closure's bed is at rest.
std::string flow_independent_note(const TrialPlanSettings& s) {
  static const std::vector<std::string> independent = {"surface_drift", "wall_mobility", "pause_creep"};
  std::string names;
  for (const auto& v : s.variants) {
    if (std::find(independent.begin(), independent.end(), v.effect) != independent.end()) {
      names += (names.empty() ? "`" : ", `") + v.effect + "`";
    }
  }
  if (names.empty()) return "";
  return "- " + names + " drift(s) at a fixed speed that does not scale with the local flow (docs/loop.md): it acts "
         "even in designs where the closure's bed never moves (tilt below the friction thresholds), so the variant's "
         "congregation there is an extrapolation of a cycle-mean fit, not a prediction of flow.\n";
}

}  // namespace

std::vector<int> congregation_ranking(const TrialSweepResult& r) {
  std::vector<int> idx(r.cases.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) {
    const double ra = r.cases[a][0].ratio, rb = r.cases[b][0].ratio;
    if (std::isfinite(ra) != std::isfinite(rb)) return std::isfinite(ra);
    return ra > rb;
  });
  return idx;
}

std::vector<std::vector<PredictedObservation>> predicted_observations(const TrialSweepResult& r) {
  std::vector<std::vector<PredictedObservation>> p(r.cases.size());
  for (std::size_t d = 0; d < r.cases.size(); ++d) {
    for (const auto& c : r.cases[d]) p[d].push_back(c.coverage);
  }
  return p;
}

std::string write_trial_report(const TrialPlanSettings& s, const TrialSweepResult& r, const std::vector<TrialStage>& stages,
                               const std::string& out) {
  const std::size_t nd = s.designs.size(), nv = s.variants.size();
  const DiscriminationSettings& ds = s.discrimination;
  const std::vector<int> rank = congregation_ranking(r);
  const std::vector<TrialScore> ranked = score_trials(predicted_observations(r), ds);
  const std::vector<TrialScore> recommended = recommended_trials(ranked, ds);
  std::vector<std::string> warnings;
  int failed = 0;
  for (std::size_t d = 0; d < nd; ++d) {
    for (std::size_t v = 0; v < nv; ++v) {
      const TrialCaseResult& c = r.cases[d][v];
      if (!c.error.empty()) {
        ++failed;
        warnings.push_back("case " + s.designs[d].label() + ", variant " + s.variants[v].name + " failed: " + c.error);
      } else if (!(c.coverage.centre > 0)) {
        warnings.push_back("case " + s.designs[d].label() + ", variant " + s.variants[v].name +
                           ": no chaff coverage in the centre zone (the ratio is undefined)");
      }
    }
  }

  // predictions.csv: every case.
  {
    std::ostringstream c;
    c << "# trial_planning " << s.name << ": every design under every variant after " << num(s.duration)
      << " s; coverage = 1 - exp(-kappa int_top c dz) in the zones (end zones of " << num(s.end_length)
      << " m, a centre zone as long); ratio = mean end / centre coverage; share = chaff in the top layer within the end zone\n"
      << "design,variant,motion,length_m,fill_height_m,amplitude_deg,period_s,coverage_left,coverage_centre,coverage_right,"
         "ratio,share_left,share_right,chaff_change,c_min,c_max,resolved_cycles,closure_steps,chaff_steps\n";
    for (std::size_t d = 0; d < nd; ++d) {
      const TrialDesign& x = s.designs[d];
      for (std::size_t v = 0; v < nv; ++v) {
        const TrialCaseResult& k = r.cases[d][v];
        c << d << "," << s.variants[v].name << "," << x.motion << "," << num(x.length) << "," << num(x.fill_height) << ","
          << num(x.amplitude_deg) << "," << num(x.period) << "," << num(k.coverage.left) << "," << num(k.coverage.centre)
          << "," << num(k.coverage.right) << "," << num(k.ratio) << "," << num(k.share_left) << "," << num(k.share_right)
          << "," << num(k.chaff_change) << "," << num(k.c_min) << "," << num(k.c_max) << "," << k.resolved_cycles << ","
          << k.closure_steps << "," << k.chaff_steps << "\n";
      }
    }
    dem::write_file_atomically((fs::path(out) / "predictions.csv").string(), c.str());
  }
  // ranking.csv and discrimination.csv.
  {
    std::ostringstream c;
    c << "rank,design,motion,length_m,fill_height_m,amplitude_deg,period_s";
    for (const auto& v : s.variants) c << ",ratio_" << v.name;
    c << "\n";
    for (std::size_t k = 0; k < nd; ++k) {
      const TrialDesign& x = s.designs[rank[k]];
      c << k + 1 << "," << x.index << "," << x.motion << "," << num(x.length) << "," << num(x.fill_height) << ","
        << num(x.amplitude_deg) << "," << num(x.period);
      for (std::size_t v = 0; v < nv; ++v) c << "," << num(r.cases[x.index][v].ratio);
      c << "\n";
    }
    dem::write_file_atomically((fs::path(out) / "ranking.csv").string(), c.str());
    std::ostringstream q;
    q << "# score = " << ds.score << " over variant pairs of sqrt(sum_k ((y_a,k - y_b,k)/sigma_k)^2), k = left, centre, right "
      << "coverage; sigma_end " << num(ds.sigma_end) << ", sigma_centre " << num(ds.sigma_centre) << "\n"
      << "rank,design,motion,length_m,fill_height_m,amplitude_deg,period_s,score,min_pair,mean_pair,closest_a,closest_b\n";
    for (std::size_t k = 0; k < ranked.size(); ++k) {
      const TrialScore& t = ranked[k];
      const TrialDesign& x = s.designs[t.design];
      q << k + 1 << "," << t.design << "," << x.motion << "," << num(x.length) << "," << num(x.fill_height) << ","
        << num(x.amplitude_deg) << "," << num(x.period) << "," << num(t.score) << "," << num(t.min_pair) << ","
        << num(t.mean_pair) << "," << (t.pair_a >= 0 ? s.variants[t.pair_a].name : "") << ","
        << (t.pair_b >= 0 ? s.variants[t.pair_b].name : "") << "\n";
    }
    dem::write_file_atomically((fs::path(out) / "discrimination.csv").string(), q.str());
  }
  write_figures(s, r, ranked, recommended, out, warnings);
  // summary.yaml
  {
    std::ostringstream y;
    y << "# trial_planning " << s.name << " (docs/studies.md)\n"
      << "designs: " << nd << "\nvariants: [";
    for (std::size_t v = 0; v < nv; ++v) y << (v ? ", " : "") << s.variants[v].name;
    y << "]\nfailed_cases: " << failed << "\nmost_congregation: {design: " << rank[0] << ", label: \""
      << s.designs[rank[0]].label() << "\", ratio: " << num(r.cases[rank[0]][0].ratio) << "}\n"
      << "least_congregation: {design: " << rank.back() << ", label: \"" << s.designs[rank.back()].label()
      << "\", ratio: " << num(r.cases[rank.back()][0].ratio) << "}\n"
      << "discriminating_trials:" << (recommended.empty() ? " []\n" : "\n");
    for (const auto& t : recommended) {
      y << "  - {design: " << t.design << ", label: \"" << s.designs[t.design].label() << "\", score: " << num(t.score) << "}\n";
    }
    dem::write_file_atomically((fs::path(out) / "summary.yaml").string(), y.str());
  }

  std::ostringstream m;
  m << "# " << s.title << "\n\n";
  if (!s.description.empty()) m << s.description << "\n\n";
  m << "Study `" << s.name << "`, run with `grainscale study " << s.source_file << "`. Inputs as run: `inputs/`; "
    << "log: `log.txt`; numbers: `predictions.csv` (every case), `ranking.csv`, `discrimination.csv`, `summary.yaml`.\n\n";
  m << "## What was run\n\n| stage | result | wall clock |\n|---|---|---|\n";
  double total = 0;
  for (const auto& st : stages) {
    m << "| " << st.name << " | " << st.what << " | " << g(st.wall_seconds, 3) << " s |\n";
    total += st.wall_seconds;
  }
  m << "| total | | " << g(total, 3) << " s (" << g(total / 60, 2) << " min) |\n\n";
  if (!warnings.empty()) {
    m << "## Warnings\n\n";
    for (std::size_t k = 0; k < std::min<std::size_t>(warnings.size(), 30); ++k) m << "- " << warnings[k] << "\n";
    if (warnings.size() > 30) m << "- ... and " << warnings.size() - 30 << " more (`log.txt`)\n";
    m << "\n";
  }

  const HoldSettings& b = s.base;
  m << "## 1. The sweep\n\n"
    << nd << " designs, each predicted with the hold-scale model (`grainscale hold`, docs/hold_prediction.md: "
    << "the depth-averaged granular flow closure on the moving container driving the chaff advection-diffusion-"
    << "segregation model on the top " << (b.window >= b.fill_height ? "of the bed (the whole fill)" : g(b.window) + " m")
    << ") for " << g(s.duration) << " s of motion under each of the " << nv << " model variants (section 3): "
    << nd * nv << " predictions. Cycles resolved: "
    << (s.resolve > 0 ? std::to_string(s.resolve) + ", then the cycle-averaged slow-time model (the last " +
                            std::to_string(s.average_cycles) + " resolved cycles averaged)"
                      : std::string("all"))
    << ". Base settings `" << s.base_file << "` (copied to `inputs/`): " << g(b.length) << " m long, fill "
    << g(b.fill_height * 1000) << " mm, " << b.nx << " x " << b.nz << " chaff cells (the cell length "
    << g(b.length / b.nx * 1000, 3) << " mm is kept for every length), internal friction "
    << g(b.friction.internal_deg, 3) << " deg, basal friction " << g(b.friction.basal_deg, 3) << " deg, chaff "
    << "initially uniform at c = " << g(b.chaff_initial, 3) << "; chaff terms:";
  for (const auto& t : b.terms) m << " `" << t.first << "`";
  m << ".\n\n| variable | values |\n|---|---|\n";
  {
    std::set<std::string> motions;
    for (const auto& d : s.designs) motions.insert(d.motion);
    std::string list;
    for (const auto& mo : motions) list += (list.empty() ? "" : ", ") + mo;
    m << "| motion | " << list << " |\n";
    for (const NumericAxis& a : numeric_axes()) {
      std::string vals;
      for (double v : values_of(s, a)) vals += (vals.empty() ? "" : ", ") + g(v);
      m << "| " << a.label << " | " << vals << " |\n";
    }
  }
  m << "\nNamed motions (the DEM's motion blocks, dem/motion/; the sweep's amplitude sets the largest tilt, its "
    << "period the cycle, pauses kept):\n\n| motion | block | section | axis (pivot) |\n|---|---|---|---|\n";
  for (const auto& mo : s.motions) {
    bool used = false;
    for (const auto& d : s.designs) used = used || d.motion == mo.name;
    if (!used) continue;
    YAML::Emitter e;
    e << YAML::Flow << mo.block;
    m << "| " << mo.name << " | `" << e.c_str() << "` | " << mo.direction << " | [" << g(mo.pivot_x) << ", "
      << g(mo.pivot_z) << "] m from the " << (mo.pivot_from_centre ? "container centre" : "x = 0 wall") << " |\n";
  }
  m << "\nWhat a trial measures, as the report did (../shared/data/source_measurements.yaml): the top-view chaff "
    << "coverage after " << g(s.duration) << " s, coverage = 1 - exp(-kappa int c dz) over the top delta "
    << "(continuum/observation.hpp; kappa = " << g(s.kappa) << " 1/m, delta = " << g(s.delta * 1000) << " mm unless a "
    << "variant sets them), averaged over the outer " << g(s.end_length * 1000) << " mm at each end and as long a "
    << "zone in the centre. Congregation = mean end coverage / centre coverage (`coverage_ratio` of "
    << "docs/coarsegrain_layout.md; 1 = uniform; the report's wheat: 60 % / 10 % = 6).\n\n";

  m << "## 2. Ranking by predicted congregation\n\n"
    << "Designs ordered by the congregation the reference variant (`" << s.variants[0].name << "`, "
    << (std::isfinite(s.variants[0].delta_bic) ? "the most plausible: lowest BIC" : "the first listed") << ") predicts; the "
    << "other variants' predictions beside it. All " << nd << " in `ranking.csv`.\n\n| rank | design | ";
  for (const auto& v : s.variants) m << v.name << " | ";
  m << "coverage ends / centre (" << s.variants[0].name << ") |\n|---|---|";
  for (std::size_t v = 0; v < nv; ++v) m << "---|";
  m << "---|\n";
  for (std::size_t k = 0; k < std::min<std::size_t>(nd, 15); ++k) {
    const int d = rank[k];
    const TrialCaseResult& c0 = r.cases[d][0];
    m << "| " << k + 1 << " | " << s.designs[d].label() << " | ";
    for (std::size_t v = 0; v < nv; ++v) m << (v == 0 ? "**" + g(r.cases[d][v].ratio, 3) + "**" : g(r.cases[d][v].ratio, 3)) << " | ";
    m << pct(0.5 * (c0.coverage.left + c0.coverage.right)) << " / " << pct(c0.coverage.centre) << " |\n";
  }
  if (nd > 15) {
    m << "| ... | | ";
    for (std::size_t v = 0; v < nv; ++v) m << " | ";
    m << " |\n| " << nd << " | " << s.designs[rank.back()].label() << " | ";
    for (std::size_t v = 0; v < nv; ++v) m << g(r.cases[rank.back()][v].ratio, 3) << " | ";
    m << " |\n";
  }
  m << "\n";
  const std::string which = swept(s, "motion") ? " (designs of motion " + main_motion(s) + ")" : "";
  for (const NumericAxis& a : numeric_axes()) {
    if (fs::exists(fs::path(out) / ("congregation_" + a.key + ".png"))) {
      m << figure(out, "congregation_" + a.key + ".png", "Congregation vs " + a.label + which + ": mean per value, and each design");
    }
  }
  if (swept(s, "motion")) m << figure(out, "congregation_motion.png", "Congregation by motion");
  m << figure(out, "congregation_map.png", "Congregation over two swept variables" + which + ", reference variant");

  m << "## 3. Model variants compared\n\n";
  if (!s.loop_file.empty()) {
    m << "From `" << s.loop_file << "` (`grainscale loop`, docs/loop.md): the loop's chosen model (`" << s.loop_chosen
      << "`"
      << (s.loop_reason.empty() ? "" : ": " + s.loop_reason) << ") and every candidate whose BIC is less than "
      << g(s.max_delta_bic) << " above the best model's"
      << (s.constrained_only ? ", with its strength constrained (standard error below the value)" : "") << ".";
    if (!s.excluded.empty()) {
      m << " Left out:";
      for (std::size_t k = 0; k < s.excluded.size(); ++k) {
        m << (k ? ";" : "") << " `" << s.excluded[k].name << "` (" << s.excluded[k].reason << ")";
      }
      m << ".";
    }
    m << "\n\n";
  }
  m << "| variant | effect added | parameters (fitted value ± standard error) | where from |\n|---|---|---|---|\n";
  for (const auto& v : s.variants) {
    std::string ps;
    for (std::size_t j = 0; j < v.parameters.size(); ++j) {
      ps += (ps.empty() ? "" : ", ") + v.parameters[j].first + " = " + g(v.parameters[j].second) +
            (j < v.errors.size() && std::isfinite(v.errors[j]) ? " ± " + g(v.errors[j], 2) : "");
    }
    m << "| " << v.name << " | " << (v.effect.empty() ? "none (base model)" : "`" + v.effect + "`") << " | "
      << (ps.empty() ? "as the base file" : ps) << " | " << v.origin << " |\n";
  }
  m << "\nAn effect's motion-derived parameters (lever_arm: mean omega^2, mean alpha^2 and the axis; pause_creep: the pause "
    << "fraction) are taken from each trial's own motion. A variant's strength was fitted with the model and flow "
    << "of its loop run, not with this closure flow (see the limits).\n\n";

  m << "## 4. Recommended trials\n\n"
    << "Each variant predicts what a trial would measure (coverage of the left end, centre and right end zones). A "
    << "trial separates two variants by d = sqrt(sum ((difference) / sigma)^2) over the three zones, with the "
    << "measurement's standard deviation sigma = " << g(ds.sigma_end) << " at the ends and " << g(ds.sigma_centre)
    << " in the centre (from " << s.sigma_source << "). Its score is the " << (ds.score == "min" ? "smallest" : "mean")
    << " d over the " << nv * (nv - 1) / 2 << " pair(s) of variants; a trial discriminates when the score reaches "
    << g(ds.min_separation) << " (a " << g(ds.min_separation) << "-sigma difference). Every design's score: "
    << "`discrimination.csv`.\n\n";
  if (nv < 2) {
    m << "Only one variant: there is nothing to discriminate. **No trial discriminates.**\n\n";
  } else if (recommended.empty()) {
    m << "**No trial discriminates**: the best score is " << g(ranked.empty() ? 0 : ranked[0].score, 3)
      << " (design " << (ranked.empty() ? std::string("-") : s.designs[ranked[0].design].label())
      << "), below " << g(ds.min_separation) << ": within this sweep the variants predict what a trial would "
      << "measure to within the measurement's uncertainty.\n\n";
  } else {
    m << "| rank | trial | score | closest pair |";
    for (const auto& v : s.variants) m << " " << v.name << ": left / centre / right |";
    m << "\n|---|---|---|---|";
    for (std::size_t v = 0; v < nv; ++v) m << "---|";
    m << "\n";
    for (std::size_t k = 0; k < recommended.size(); ++k) {
      const TrialScore& t = recommended[k];
      m << "| " << k + 1 << " | " << s.designs[t.design].label() << " | " << g(t.score, 3) << " | "
        << s.variants[t.pair_a].name << " vs " << s.variants[t.pair_b].name << " |";
      for (std::size_t v = 0; v < nv; ++v) {
        const PredictedObservation& o = r.cases[t.design][v].coverage;
        m << " " << pct(o.left) << " / " << pct(o.centre) << " / " << pct(o.right) << " |";
      }
      m << "\n";
    }
    m << "\nWhy: ";
    const TrialScore& t0 = recommended[0];
    const TrialDesign& d0 = s.designs[t0.design];
    const PredictedObservation &a = r.cases[t0.design][t0.pair_a].coverage, &bb = r.cases[t0.design][t0.pair_b].coverage;
    m << "in the first trial (" << d0.label() << ") even the closest pair, `" << s.variants[t0.pair_a].name << "` and `"
      << s.variants[t0.pair_b].name << "`, predict end coverage " << pct(0.5 * (a.left + a.right)) << " vs "
      << pct(0.5 * (bb.left + bb.right)) << " and centre coverage " << pct(a.centre) << " vs " << pct(bb.centre)
      << ", " << g(t0.score, 3) << " sigma apart";
    const TrialScore& worst = ranked.back();
    m << "; the least informative design of the sweep (" << s.designs[worst.design].label() << ") separates them by "
      << "only " << g(worst.score, 3) << " sigma.";
    for (const NumericAxis& ax : numeric_axes()) {
      if (!swept(s, ax.key)) continue;
      const std::vector<double> vals = values_of(s, ax);
      double best_v = NAN, best_s = -1;
      for (double x : vals) {
        for (const auto& t : ranked) {
          if (ax.get(s.designs[t.design]) == x && t.score > best_s) best_s = t.score, best_v = x;
        }
      }
      m << " Best " << ax.label << ": " << g(best_v) << ".";
    }
    m << "\n\n";
  }
  const std::vector<TrialScore>& shown = recommended.empty() ? ranked : recommended;
  for (std::size_t k = 0; k < std::min<std::size_t>(3, shown.size()); ++k) {
    m << figure(out, "trial_" + std::to_string(k + 1) + ".png",
                "Predicted coverage along the container under each variant, " +
                    std::string(recommended.empty() ? "best-scored design " : "recommended trial ") +
                    std::to_string(k + 1) + " (points: zone means)");
  }
  for (const NumericAxis& a : numeric_axes()) {
    if (fs::exists(fs::path(out) / ("discrimination_" + a.key + ".png"))) {
      m << figure(out, "discrimination_" + a.key + ".png", "Discrimination score vs " + a.label + which);
    }
  }

  m << "## Limits\n\n"
    << "- The flow is the 2-D depth-averaged closure (one section along the motion; no side walls, no 3-D "
    << "circulation), **not validated at any scale yet** (docs/hold_prediction.md: against the DEM platform demo "
    << "its onset is late and its speeds 50-80 % high); congregation numbers are comparisons between designs "
    << "under one model, not forecasts.\n"
    << "- The chaff grid keeps the initial flat surface (the bed's own reshaping is not in the chaff model), and the "
    << "cycle-averaged slow-time model, where used, has no within-cycle sloshing.\n"
    << "- The variants' strengths were fitted by the loop with its own model and flow (for the report's wheat: a "
    << "uniform-shear stand-in, three coverage numbers) and are carried over unchanged to every design; an effect "
    << "whose strength depends on the container or the motion is extrapolated.\n"
    << flow_independent_note(s)
    << "- The measurement uncertainty is the report's photograph analysis; a trial with better lighting or "
    << "repeated photographs has smaller sigma and separates more.\n"
    << "- Only the designs in the sweep are ranked; the best trial may lie between or beyond them.\n";
  const std::string path = (fs::path(out) / "report.md").string();
  dem::write_file_atomically(path, m.str());
  return path;
}

}  // namespace grainscale::studies
