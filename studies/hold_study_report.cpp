#include "studies/hold_study_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <sstream>

#include "dem/atomic_file.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

std::string g(double v, int digits = 4) {
  if (!std::isfinite(v)) return "n/a";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string pct(double v) { return std::isfinite(v) ? g(100 * v, 3) + " %" : "n/a"; }

/// Time in the unit a reader wants: s up to two hours, then h.
std::string when(double t) { return t > 7200 ? g(t / 3600, 3) + " h" : g(t, 4) + " s"; }

std::string figure(const std::string& out, const std::string& rel, const std::string& caption) {
  if (!fs::exists(fs::path(out) / rel)) return "*(" + caption + ": not drawn)*\n\n";
  return "![" + caption + "](" + rel + ")\n\n*" + caption + "*\n\n";
}

std::string dirty_text(const HoldScenarioOutcome& o) {
  if (o.dirty.empty()) return "nowhere";
  std::string t;
  for (const auto& [a, b] : o.dirty) t += (t.empty() ? "" : ", ") + g(a, 3) + "-" + g(b, 3) + " m";
  return t;
}

/// A word for an end enrichment E (1: as mixed at loading).
std::string congregation_word(double e) {
  if (!std::isfinite(e)) return "n/a";
  if (e < 1.1) return "none";
  if (e < 1.5) return "slight";
  if (e < 3) return "clear";
  return "strong";
}

}  // namespace

double report_visible_chaff_ratio() { return std::log(1 - 0.60) / std::log(1 - 0.10); }

std::string write_hold_study_report(const HoldStudySettings& s, const HoldStudyResults& r, const std::string& out) {
  std::ostringstream m;
  m << "# " << s.title << "\n\n";
  if (!s.description.empty()) m << s.description << "\n\n";
  m << "Study `" << s.name << "` (kind `hold`), run with `grainscale study " << s.source_file
    << "`. Each scenario is a `grainscale hold` run (flow closure + chaff model, docs/hold_prediction.md) in its "
    << "own subfolder, which holds its CSV, `continuum.h5`, figures and `summary.yaml`; a scenario reruns alone with "
    << "`grainscale hold inputs/FILE --out DIR`. Inputs as run: `inputs/`; log: `log.txt`.\n\n";

  m << "## What was run\n\n| scenario | settings file | container and motion | simulated | cycles resolved | closure / "
       "chaff steps | wall clock | per simulated day |\n|---|---|---|---|---|---|---|---|\n";
  double total = 0;
  for (const auto& o : r.scenarios) {
    m << "| `" << o.name << "` | `" << fs::path(o.file).filename().string() << "` | " << o.what << " | " << when(o.t_end)
      << (o.shortened ? " (shortened from " + when(o.file_end) + ")" : "") << " | " << o.resolved_chunks << " of "
      << o.total_chunks << " (" << g(o.chunk, 3) << " s)" << (o.averaged ? ", then cycle-averaged" : "") << " | "
      << o.closure_steps << " / " << o.chaff_steps << " | " << g(o.wall_seconds, 3) << " s | "
      << g(o.wall_seconds / o.t_end * 86400, 3) << " s |\n";
    total += o.wall_seconds;
  }
  m << "| total | | | | | | " << g(r.wall_seconds, 3) << " s (" << g(r.wall_seconds / 60, 2) << " min; scenarios "
    << g(total, 3) << " s) | |\n\n";

  if (!r.warnings.empty()) {
    m << "## Warnings\n\n";
    for (const auto& w : r.warnings) m << "- " << w << "\n";
    m << "\n";
  }

  // Ranking by predicted congregation.
  std::vector<std::size_t> order(r.scenarios.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const double ea = r.scenarios[a].enrichment(), eb = r.scenarios[b].enrichment();
    return (std::isfinite(ea) ? ea : -1) > (std::isfinite(eb) ? eb : -1);
  });
  m << "## Summary: scenarios ranked by predicted congregation\n\n"
    << "End enrichment E = (share of all modelled chaff in the top layer within the end zone of a wall) / (the same "
    << "share were the chaff still mixed as loaded): 1 means no congregation at that end, 2 twice the chaff there. "
    << "Ranked by the larger end's E at the end of each run. Surface c: the chaff volume fraction of the top cell, "
    << "mean over the end zone, over the value at loading. Spear: the largest mean chaff fraction a spear sample "
    << "of the scenario's spear depth collects anywhere along the section, over the value at loading; dirty above "
    << "the scenario's `dirty_factor`.\n\n"
    << "| rank | scenario | simulated | E left | E right | surface c left / right end (x loading) | spear max (x "
       "loading) | dirty grain at | congregation |\n|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto& o = r.scenarios[order[k]];
    m << "| " << k + 1 << " | `" << o.name << "` | " << when(o.t_end) << " | " << g(o.enrichment_left, 3) << " | "
      << g(o.enrichment_right, 3) << " | " << g(o.surface_left.back() / o.c_initial, 3) << " / "
      << g(o.surface_right.back() / o.c_initial, 3) << " | " << g(o.spear_max / o.c_initial, 3) << " | "
      << dirty_text(o) << " | " << congregation_word(o.enrichment()) << " |\n";
  }
  m << "\n";
  if (!order.empty()) {
    const auto& top = r.scenarios[order.front()];
    const bool any_dirty = std::any_of(r.scenarios.begin(), r.scenarios.end(), [](const auto& o) { return !o.dirty.empty(); });
    m << "Verdict: the most congregation is predicted in `" << top.name << "` (E = " << g(top.enrichment(), 3) << ", "
      << congregation_word(top.enrichment()) << ")";
    if (order.size() > 1) {
      const auto& last = r.scenarios[order.back()];
      m << ", the least in `" << last.name << "` (E = " << g(last.enrichment(), 3) << ")";
    }
    m << ". " << (any_dirty ? "A spear sample finds dirty grain in at least one scenario (table)."
                            : "No spear sample finds dirty grain in any scenario.")
      << " These are predictions of an unvalidated closure with assumed segregation and diffusion coefficients "
      << "(Limits).\n\n";
  }

  for (std::size_t k = 0; k < r.scenarios.size(); ++k) {
    const auto& o = r.scenarios[k];
    m << "## Scenario " << k + 1 << ": " << o.name << "\n\n"
      << "`" << o.file << "`: " << o.what << ", " << when(o.t_end) << " of motion"
      << (o.averaged ? " (" + std::to_string(o.resolved_chunks) + " cycles resolved, then the cycle-averaged slow-time "
                           "model: the later fields are cycle means)"
                     : " (every cycle resolved)")
      << ". Chaff at loading c = " << g(o.c_initial, 3) << " by volume, conserved to " << g(o.chaff_relative_change, 2)
      << " (relative); c at the end in [" << g(o.c_min, 3) << ", " << g(o.c_max, 3) << "]. End zones: "
      << g(o.end_zone, 3) << " m from each wall; top layer " << g(o.top_layer, 3) << " m (uniform share "
      << pct(o.uniform_left) << " left, " << pct(o.uniform_right) << " right); centre zone " << g(o.end_zone, 3)
      << " m wide. Folder: `" << o.folder << "/`.\n\n"
      << "Chaff build-up over time:\n\n| t | surface c, left end | surface c, centre | surface c, right end | share "
         "in top layer, left end | share in top layer, right end |\n|---|---|---|---|---|---|\n";
    const std::size_t n = o.times.size(), rows = std::min<std::size_t>(n, 9);
    std::size_t last = n;  // no row twice
    for (std::size_t j = 0; j < rows; ++j) {
      const std::size_t i = rows > 1 ? j * (n - 1) / (rows - 1) : 0;
      if (i == last) continue;
      last = i;
      m << "| " << when(o.times[i]) << " | " << g(o.surface_left[i], 4) << " | " << g(o.surface_centre[i], 4) << " | "
        << g(o.surface_right[i], 4) << " | " << pct(o.left_share[i]) << " | " << pct(o.right_share[i]) << " |\n";
    }
    m << "\nEvery output time: `" << o.folder << "/surface_chaff.csv`, `" << o.folder << "/end_fractions.csv`.\n\n"
      << "Spear (" << g(o.spear_depth, 3) << " m, pushed in from the surface at the end of the run): largest mean "
      << g(o.spear_max, 3) << " (" << g(o.spear_max / o.c_initial, 3) << " x loading); dirty (above "
      << g(o.dirty_factor, 3) << " x loading): " << dirty_text(o) << " (`" << o.folder << "/spear.csv`).\n\n";
    const std::string p = o.folder + "/";
    m << figure(out, p + "surface_chaff.png", o.name + ": chaff in the top cell along the section over time")
      << figure(out, p + "end_fractions.png", o.name + ": share of the chaff in the top layer near each end wall")
      << figure(out, p + "chaff_map.png", o.name + ": chaff in the modelled top window at the end")
      << figure(out, p + "spear.png", o.name + ": what a spear sample finds at the end")
      << figure(out, p + "surface.png", o.name + ": bed depth from the flow closure, start and end");
  }

  m << "## Cost: one day of motion\n\n"
    << "Issue 8 asks for one day of rolling in a hold, 2-D, in at most 10 minutes (600 s) on 2 cores. Each run is "
    << "one thread (closure and chaff model are sequential); the wall clock depends on what else the machine runs.\n\n"
    << "| scenario | simulated | wall clock | wall clock per simulated day | within 600 s per day |\n|---|---|---|---|---|\n";
  for (const auto& o : r.scenarios) {
    const double per_day = o.wall_seconds / o.t_end * 86400;
    m << "| `" << o.name << "` | " << when(o.t_end) << " | " << g(o.wall_seconds, 3) << " s | " << g(per_day, 3) << " s | "
      << (per_day <= 600 ? "yes" : "**no**") << (o.averaged ? " (cycle-averaged after " + std::to_string(o.resolved_chunks) + " cycles)" : "")
      << " |\n";
  }
  m << "\nA shortened run's per-day figure is extrapolated linearly from its resolved cycles; a run that switches to "
    << "the cycle-averaged model covers the rest of the day in seconds, so its per-day figure is an upper bound.\n\n";

  m << "## Comparison with the measurements\n\n"
    << "The source report measured one thing these scenarios can be held against: the top-view chaff coverage of "
    << "wheat after 30 minutes in its 800 mm box on the platform, about 10 % in the centre and about 60 % at the "
    << "ends, of which only the right-hand peak is trustworthy (../shared/data/source_measurements.yaml). Through "
    << "the coverage operator (O1) of docs/continuum.md, coverage = 1 - exp(-kappa * chaff in the visible top "
    << "layer), the measured pair means " << g(report_visible_chaff_ratio(), 3)
    << " times as much chaff in the visible top layer (one grain diameter) at the right end as in the centre, "
    << "whatever kappa is. Ships, trucks and chaser bins have no measurements.\n\n";
  bool compared = false;
  for (const auto& o : r.scenarios) {
    if (!o.compare_with_report) continue;
    compared = true;
    const double ratio = report_visible_chaff_ratio();
    const double rr = o.visible_ratio_right;
    m << "| `" << o.name << "` after " << when(o.t_end) << " | predicted | measured |\n|---|---|---|\n"
      << "| visible chaff, right end / centre | " << g(rr, 3) << " | " << g(ratio, 3) << " |\n"
      << "| visible chaff, left end / centre | " << g(o.visible_ratio_left, 3) << " | (artefact) |\n\n";
    std::string verdict;
    if (!std::isfinite(rr)) verdict = "no comparison (no chaff in the centre zone)";
    else if (rr >= ratio / 2 && rr <= ratio * 2) verdict = "the prediction is within a factor of 2 of the measurement";
    else if (rr < ratio / 2) verdict = "the prediction falls short of the measured congregation by more than a factor of 2";
    else verdict = "the prediction exceeds the measured congregation by more than a factor of 2";
    m << "Verdict for `" << o.name << "`: " << verdict
      << (std::fabs(o.t_end - 1800) > 1 ? " (note: compared after " + when(o.t_end) + ", the report's photograph is at 30 min)" : "")
      << ".\n\n";
  }
  if (!compared) m << "No scenario of this study is marked `compare_with_report: true`, so none is compared.\n\n";

  m << "## Closure vs DEM\n\n";
  if (r.validation) {
    const ClosureDemComparison& v = *r.validation;
    m << "The flow closure against the coarse-grained DEM flow of `" << v.dem_scenario << "` (fields `" << v.cg_fields
      << "`): the same box (" << g(v.box_length, 3) << " m), pivot and motion, filled to the DEM's mean surface height ("
      << g(1000 * v.fill_height, 3) << " mm), with the bed friction of `" << v.material_from << "`, "
      << (std::isfinite(v.flowing_layer) ? "a flowing layer of " + g(1000 * v.flowing_layer, 3) + " mm"
                                         : std::string("moving as a plug (the whole depth)"))
      << " and the friction of the box's side walls, mu_w a/W with W = "
      << g(1000 * v.side_wall_width, 3) << " mm and mu_w = " << g(v.side_wall_friction, 3) << " (the DEM's grain-wall "
      << "sliding friction; Jop, Forterre & Pouliquen 2005); the 2-D closure without side walls beside it. Measures "
      << "per frame: the free-surface angle to the horizontal (tilt + least-squares slope of h(x) in the box frame) "
      << "and the surface speed along the box, averaged over the top " << g(1000 * v.measure_depth, 3)
      << " mm of the bed (closure_dem_comparison.hpp).\n\n"
      << "| t (s) | tilt (deg) | surface angle DEM (deg) | closure (deg) | 2-D closure (deg) | surface speed DEM (m/s) | "
         "closure (m/s) | 2-D closure (m/s) |\n"
      << "|---|---|---|---|---|---|---|---|\n";
    const std::size_t n = v.times.size(), step = (n + 19) / 20;  // at most 20 rows; all in the CSV
    for (std::size_t j = 0; j < n; j += step) {
      m << "| " << g(v.times[j], 4) << " | " << g(v.tilt_deg[j], 3) << " | " << g(v.dem_angle_deg[j], 3) << " | "
        << g(v.closure_angle_deg[j], 3) << " | " << g(v.open_angle_deg[j], 3) << " | " << g(v.dem_speed[j], 3) << " | "
        << g(v.closure_speed[j], 3) << " | " << g(v.open_speed[j], 3) << " |\n";
    }
    m << "\n| error over " << v.times.size() << " frames | RMS | max | 2-D closure: RMS | max |\n|---|---|---|---|---|\n"
      << "| free-surface angle | " << g(v.angle_rms_error_deg, 3) << " deg | " << g(v.angle_max_error_deg, 3) << " deg | "
      << g(v.open_angle_rms_error_deg, 3) << " deg | " << g(v.open_angle_max_error_deg, 3) << " deg |\n"
      << "| surface speed | " << g(v.speed_rms_error, 3) << " m/s (DEM RMS speed " << g(v.dem_speed_rms, 3) << " m/s) | "
      << g(v.speed_max_error, 3) << " m/s | " << g(v.open_speed_rms_error, 3) << " m/s | " << g(v.open_speed_max_error, 3)
      << " m/s |\n\n"
      << (step > 1 ? "One frame in " + std::to_string(step) + " shown; all in `closure_vs_dem/comparison.csv`.\n\n" : "")
      << "Verdict: the closure with side walls " << (v.agrees ? "**reproduces**" : "**does not reproduce**")
      << " this DEM flow (bar: surface angle within " << g(kAngleTolerance, 2) << " deg RMS and surface speed within "
      << g(100 * kSpeedTolerance, 2) << " % of the DEM's RMS speed, at least " << g(kSpeedFloor, 2) << " m/s).\n\n"
      << "Null model: the bed of the first frame held rigid in the box (no flow at all) is off by "
      << g(v.still_angle_rms_error_deg, 3) << " deg and " << g(v.still_speed_rms_error, 3) << " m/s RMS, and "
      << (v.still_agrees ? "**passes the bar too**: on this DEM run the bar cannot tell a closure that flows right "
                           "from one that does not flow; compare the closure's errors with these."
                         : "fails the bar: the DEM bed flows, and the bar asks the closure to follow it.")
      << "\n\n";
    if (v.fit) {
      const ClosureFit& f = *v.fit;
      m << "### The closure's bed friction calibrated on the early frames\n\n"
        << "Fitted to the " << f.fitted_train.frames << " frames with t <= " << g(f.settings.train_until, 4)
        << " s, judged on the " << f.fitted_test.frames << " later ones it never saw (a hold-out in time; "
        << "closure_friction_fit.hpp): objective J = (angle RMS / " << g(kAngleTolerance, 2) << " deg)^2 + (speed RMS / "
        << g(kSpeedTolerance, 2) << " DEM RMS speed)^2 on the training frames, a grid then Nelder-Mead, "
        << f.evaluations << " closure runs. Range: each parameter alone, the others at the fit, where the training J "
           "rises by at most 0.25 (the errors grow by at most half the bar in quadrature; a sensitivity, not a confidence interval).\n\n"
        << "| parameter | a priori (`" << v.material_from << "`) | fitted | range |\n|---|---|---|---|\n";
      for (std::size_t j = 0; j < f.names.size(); ++j) {
        m << "| " << f.names[j] << " | " << g(f.a_priori[j], 4) << " | **" << g(f.fitted[j], 4) << "** | "
          << g(f.lower[j], 3) << " to " << g(f.upper[j], 3) << " |\n";
      }
      auto row = [&](const char* what, const BlockErrors& e) {
        m << "| " << what << " | " << e.frames << " | " << g(e.angle_rms_deg, 3) << " deg | " << g(e.speed_rms, 3)
          << " m/s (DEM RMS " << g(e.dem_speed_rms, 3) << ") | " << g(e.objective, 3) << " | "
          << (e.agrees ? "**yes**" : "no") << " |\n";
      };
      m << "\n| closure, block | frames | surface angle RMS | surface speed RMS | J | bar |\n|---|---|---|---|---|---|\n";
      row("a priori, training", f.a_priori_train);
      row("a priori, test", f.a_priori_test);
      row("fitted, training", f.fitted_train);
      row("fitted, test (held out)", f.fitted_test);
      m << "\nVerdict on the held-out frames: the calibrated closure " << (f.fitted_test.agrees ? "**reproduces**" : "**does not reproduce**")
        << " the DEM flow by the same bar.\n\n";
    }
    for (const auto& f : v.figures) m << figure(out, "closure_vs_dem/" + f, "closure vs coarse-grained DEM: " + f);
    for (const auto& n : v.notes) m << "- " << n << "\n";
    m << "\n";
  } else {
    m << "Not run in this study (add `validate: {cg_fields: ..., dem_scenario: ..., material_from: ...}`, "
      << "docs/studies.md). The closure has been compared only with a DEM layer less than one grain deep "
      << "(docs/hold_prediction.md, \"Validation against the DEM platform demo\"): not validated.\n\n";
  }

  m << "## Limits\n\n"
    << "- **2-D sections.** Each scenario is one vertical section (across the hold for roll, along it for pitch) "
       "between two vertical end walls; no variation along the other horizontal axis, no hopper or wing tanks, "
       "no hatch coaming. The side walls enter only as a friction mu_w a/W where a scenario states its width "
       "(docs/hold_prediction.md, \"Side walls\"; about 1e-3 of the friction in a ship's hold).\n"
    << "- **The flow closure is not validated at scale.** It is a depth-averaged Savage-Hutter bed with an assumed "
       "exponential velocity profile through depth and friction from the calibrated material; "
    << (r.validation ? "this study compares it with the coarse-grained DEM of one platform box (section above), "
                       "not with anything the size of a hold. "
                     : "this study does not compare it with DEM (a `validate:` block does; docs/hold_prediction.md). ")
    << "Calibrated on DEM, it reproduces a 4-grain plug sliding in the 800 mm box and a 15-grain deep bed "
       "(docs/hold_prediction.md, \"the whole cycle\", \"A deep bed\"); the deep bed calibrates a slow creep "
       "(flowing layer 2.3 d, delta_mu 4.45), which the Handysize scenarios use, against the dense-flow law "
       "(10 d, 0.26) of the literature; in a full Handysize hold the dense-flow law puts the chaff at the end "
       "walls and the calibrated one on the centreline (studies/hold_closure_sensitivity.yaml): the friction "
       "law decides where chaff goes.\n"
    << "- **Chaff coefficients are assumed**, not fitted at these scales: segregation S and shear diffusion C come "
       "from each settings file. The ranking depends on them (segregation against diffusion).\n"
    << "- **The chaff grid keeps its initial surface** (docs/hold_prediction.md): the surface layer is carried at "
       "the surface speed with a closing return flow; deposition that raises the surface at the low end is not in "
       "the chaff grid.\n"
    << "- **Cycle-averaged runs** give cycle-mean fields after the switch: no within-cycle sloshing in the maps.\n"
    << "- **Motion** is sinusoidal or the report's platform profile, not a measured ship record; Coriolis is left "
       "out (< 1 % of g).\n";
  const std::string path = (fs::path(out) / "report.md").string();
  dem::write_file_atomically(path, m.str());
  return path;
}

}  // namespace grainscale::studies
