#include "studies/ensemble_report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "dem/atomic_file.hpp"
#include "studies/ensemble_comparison.hpp"
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

std::string csv_number(double v) {
  if (!std::isfinite(v)) return "nan";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string get(const std::map<std::string, std::string>& m, const std::string& k) {
  const auto it = m.find(k);
  return it == m.end() ? "n/a" : it->second;
}

std::string stats_cell(const SampleStats& s) {
  if (s.n == 0) return "n/a";
  return g(s.mean) + (s.n > 1 ? " ± " + g(s.sd, 2) : "") + " (n = " + std::to_string(s.n) + ")";
}

std::string interval_cell(const WelchInterval& w, double pct) {
  if (!w.defined) return g(w.difference) + " (no interval: fewer than 2 seeds)";
  return g(w.difference) + " [" + g(w.lo) + ", " + g(w.hi) + "] (" + g(pct, 3) + " %, dof " + g(w.dof, 3) + ")";
}

/// A figure line if the file exists (relative to the report), else a note.
std::string figure(const std::string& out, const std::string& rel, const std::string& caption) {
  if (!fs::exists(fs::path(out) / rel)) return "*(" + caption + ": not drawn)*\n\n";
  return "![" + caption + "](" + rel + ")\n\n*" + caption + "*\n\n";
}

/// Draw a figure; a figure with nothing to draw becomes a warning instead of an error.
template <class Figure>
void draw_to(const Figure& f, const std::string& file, std::vector<std::string>& skipped) {
  try {
    draw(f).write_png(file);
  } catch (const std::exception& e) {
    skipped.push_back(fs::path(file).filename().string() + ": " + e.what());
  }
}

Axes axes(const std::string& title, const std::string& x, const std::string& y) {
  Axes a;
  a.title = title, a.x_label = x, a.y_label = y;
  return a;
}

std::vector<double> means(const std::vector<SampleStats>& v) {
  std::vector<double> out;
  for (const auto& s : v) out.push_back(s.mean);
  return out;
}

const MeasureComparison* find(const EnsembleComparison& c, const std::string& key) {
  for (const auto& m : c.measures) {
    if (m.key == key) return &m;
  }
  return nullptr;
}

std::string compartments_cell(const RunMeasures& m, bool end) {
  std::string s;
  for (const auto& c : m.compartments) {
    if (!s.empty()) s += "; ";
    s += g(end ? c.left_end : c.left_start, 3) + " / " + g(end ? c.right_end : c.right_start, 3);
  }
  return s;
}

}  // namespace

void write_run_measures(const std::string& file, const EnsembleRunRecord& r) {
  const RunMeasures& m = r.measures;
  std::ostringstream o;
  o << "key,value\nseed," << r.seed << "\nscale_factor," << csv_number(r.scale_factor) << "\nt_start_s,"
    << csv_number(m.t_start) << "\nt_end_s," << csv_number(m.t_end) << "\ngrain_bodies," << m.grain_bodies
    << "\nchaff_bodies," << m.chaff_bodies << "\nindex_start," << csv_number(m.index_start) << "\nindex_end,"
    << csv_number(m.index_end) << "\nbulk_density_kg_m3," << csv_number(m.bulk_density) << "\nbed_height_m,"
    << csv_number(m.bed_height) << "\nsurface_speed_m_s," << csv_number(m.surface_speed) << "\nmotion_frames,"
    << m.motion_frames << "\naor_deg," << csv_number(r.aor_deg) << "\naor_sector_spread_deg," << csv_number(r.aor_spread_deg)
    << "\n";
  for (std::size_t k = 0; k < m.compartments.size(); ++k) {
    const CompartmentIndex& c = m.compartments[k];
    const std::string p = "compartment_" + std::to_string(k + 1) + "_";
    o << p << "x_lo_m," << csv_number(c.x_lo) << "\n" << p << "x_hi_m," << csv_number(c.x_hi) << "\n" << p
      << "index_left_start," << csv_number(c.left_start) << "\n" << p << "index_right_start," << csv_number(c.right_start)
      << "\n" << p << "index_left_end," << csv_number(c.left_end) << "\n" << p << "index_right_end,"
      << csv_number(c.right_end) << "\n";
  }
  dem::write_file_atomically(file, o.str());
}

std::string write_ensemble_report(const EnsembleSettings& s, const EnsembleResults& r, const std::string& out) {
  const EnsembleComparison c = compare_variants(s, r);
  const std::size_t nv = s.variants.size();
  const std::string& ref_label = s.variants[c.reference].label;
  std::vector<std::string> skipped;
  const double pct = 100 * s.confidence;

  // Tables.
  {
    std::ostringstream o;
    o << "variant,seed,scale_factor,status,wall_clock_s,spheres,bodies,simulated_time_s,time_step_s,index_start,"
         "index_end,bulk_density_kg_m3,bed_height_m,surface_speed_m_s,aor_deg,compartments,compartment_index_left_end,"
         "compartment_index_right_end\n";
    for (const auto& run : r.runs) {
      const RunMeasures& m = run.measures;
      std::string lefts, rights;
      for (const auto& cp : m.compartments) {
        // (Appended piece by piece: "sep" + string made GCC 12 warn of an overlapping memcpy, -Wrestrict.)
        if (!lefts.empty()) lefts += ' ', rights += ' ';
        lefts += csv_number(cp.left_end);
        rights += csv_number(cp.right_end);
      }
      o << run.variant << ',' << run.seed << ',' << csv_number(run.scale_factor) << ',' << run.status << ','
        << csv_number(run.wall_seconds) << ',' << get(run.dem_summary, "spheres") << ',' << get(run.dem_summary, "bodies")
        << ',' << get(run.dem_summary, "simulated_time_s") << ',' << get(run.dem_summary, "time_step_s") << ','
        << csv_number(m.index_start) << ',' << csv_number(m.index_end) << ',' << csv_number(m.bulk_density) << ','
        << csv_number(m.bed_height) << ',' << csv_number(m.surface_speed) << ',' << csv_number(run.aor_deg) << ','
        << m.compartments.size() << ',' << lefts << ',' << rights << '\n';
    }
    dem::write_file_atomically(out + "/runs.csv", o.str());
    std::ostringstream sl;
    sl << "variant,seed,x_lo_m,x_hi_m,chaff_percent_start,chaff_percent_end,relative_chaff_end\n";
    for (const auto& run : r.runs) {
      const RunMeasures& m = run.measures;
      for (std::size_t k = 0; k < m.slice_lo.size(); ++k) {
        sl << run.variant << ',' << run.seed << ',' << csv_number(m.slice_lo[k]) << ',' << csv_number(m.slice_hi[k]) << ','
           << csv_number(m.chaff_percent_start[k]) << ',' << csv_number(m.chaff_percent_end[k]) << ','
           << csv_number(m.relative_chaff_end[k]) << '\n';
      }
    }
    dem::write_file_atomically(out + "/slices.csv", sl.str());
  }

  // Figures.
  const std::vector<double>& lo = c.field.slice_lo;
  std::vector<double> edges = lo, centres;
  if (!lo.empty()) edges.push_back(c.field.slice_hi.back());
  for (std::size_t k = 0; k < lo.size(); ++k) centres.push_back(0.5 * (lo[k] + c.field.slice_hi[k]));
  if (!lo.empty()) {
    BarChart end;
    end.axes = axes("Chaff per slice at the end (mean over seeds)", "x along the box (m)", "% of all chaff");
    end.edges = edges;
    for (std::size_t v = 0; v < nv; ++v) end.series.push_back({s.variants[v].label, means(c.percent_end[v])});
    draw_to(end, out + "/slices_end.png", skipped);
    for (std::size_t v = 0; v < nv; ++v) {
      BarChart b;
      b.axes = axes("Chaff per slice: " + s.variants[v].label + " (mean over seeds)", "x along the box (m)", "% of all chaff");
      b.edges = edges;
      b.series.push_back({"motion start", means(c.percent_start[v])});
      b.series.push_back({"end", means(c.percent_end[v])});
      draw_to(b, out + "/slices_" + s.variants[v].name + ".png", skipped);
    }
    LinePlot rel;
    rel.axes = axes("Relative chaff concentration per slice at the end", "x along the box (m)",
                "slice chaff fraction / box chaff fraction");
    for (std::size_t v = 0; v < nv; ++v) {
      Series mean{s.variants[v].label + " (mean)", centres, means(c.field.per_variant[v])};
      mean.marker = Marker::circle;
      mean.colour = palette(v);
      Series up{"", centres, {}}, down{"", centres, {}};
      for (const auto& st : c.field.per_variant[v]) {
        up.y.push_back(st.n > 1 ? st.mean + st.sd : NAN);
        down.y.push_back(st.n > 1 ? st.mean - st.sd : NAN);
      }
      up.line = down.line = LineStyle::dashed;
      up.colour = down.colour = palette(v);
      up.width = down.width = 1;
      rel.series.push_back(mean);
      rel.series.push_back(up);
      rel.series.push_back(down);
    }
    draw_to(rel, out + "/relative_chaff.png", skipped);
  }
  {
    LinePlot ip;
    ip.axes = axes("Congregation index per run (crosses: motion start)", "variant (1, 2, ...; seeds side by side)",
                   "mean end index of the compartments");
    for (std::size_t v = 0; v < nv; ++v) {
      Series end{s.variants[v].label + ", end", {}, {}}, start{"", {}, {}};
      const auto runs = runs_of(r, s.variants[v].name);
      for (std::size_t k = 0; k < runs.size(); ++k) {
        const double x = v + 1 + (runs.size() > 1 ? 0.3 * (double(k) / (runs.size() - 1) - 0.5) : 0);
        end.x.push_back(x), end.y.push_back(runs[k]->measures.index_end);
        start.x.push_back(x), start.y.push_back(runs[k]->measures.index_start);
      }
      end.line = LineStyle::none, end.marker = Marker::circle, end.colour = palette(v);
      start.line = LineStyle::none, start.marker = Marker::cross, start.colour = palette(v);
      ip.series.push_back(end);
      ip.series.push_back(start);
    }
    ip.axes.x_min = 0.5, ip.axes.x_max = nv + 0.5;
    draw_to(ip, out + "/index.png", skipped);
  }

  // The report.
  std::ostringstream m;
  m << "# " << s.title << "\n\n";
  if (!s.description.empty()) m << s.description << "\n\n";
  m << "Study `" << s.name << "` (ensemble: " << nv << " variants x " << s.seeds.size() << " seeds), run with `grainscale study "
    << s.source_file << "`. Inputs as run: `inputs/`; each run's folder `runs/<variant>/seed_<seed>/` holds its "
    << "scenario (`grainscale dem scenario.yaml` repeats it), its coarse-graining settings (`cg.yaml`), `dem/`, `cg/` "
    << "and `measures.csv`; all runs: `runs.csv`, `slices.csv`; log: `log.txt`.\n\n";

  m << "## What was run\n\n| run | variant | seed | scale | status | spheres | bodies | simulated (s) | time step (s) | wall clock |\n"
       "|---|---|---|---|---|---|---|---|---|---|\n";
  double total = 0;
  for (const auto& run : r.runs) {
    m << "| `" << run.folder << "` | " << run.variant << " | " << run.seed << " | " << g(run.scale_factor) << "x | "
      << run.status << " | " << get(run.dem_summary, "spheres") << " | " << get(run.dem_summary, "bodies") << " | "
      << get(run.dem_summary, "simulated_time_s") << " | " << get(run.dem_summary, "time_step_s") << " | "
      << g(run.wall_seconds, 3) << " s |\n";
    total += run.wall_seconds;
  }
  m << "| total | | | | | | | | | " << g(total, 3) << " s (" << g(total / 3600, 3) << " h); this session "
    << g(r.wall_seconds, 3) << " s |\n\n";
  m << "Variants: ";
  for (std::size_t v = 0; v < nv; ++v) {
    m << (v ? "; " : "") << "**" << s.variants[v].label << "** (`" << s.variants[v].name << "`, "
      << fs::path(s.variants[v].scenario).filename().string()
      << (s.variants[v].scale_factor ? ", scale_factor " + g(*s.variants[v].scale_factor) : std::string()) << ")";
  }
  m << ". Reference: **" << ref_label << "**. Coarse-graining: `" << fs::path(s.cg_settings).filename().string()
    << "` on every snapshot; motion start (the \"before\" snapshot) at " << g(s.motion_from) << " s.\n\n";

  m << "## Warnings\n\n";
  if (r.warnings.empty() && skipped.empty()) m << "None.\n";
  for (const auto& w : r.warnings) m << "- " << w << "\n";
  for (const auto& w : skipped) m << "- figure not drawn: " << w << "\n";
  m << "\n";

  m << "## Measures per run\n\n"
       "Congregation index: chaff bodies / all bodies in each end zone (the outer "
    << "end_length of each compartment, from the coarse-graining settings) over the same in the compartment; 1 is "
       "uniform (coarsegrain/congregation_index.hpp). Per compartment: left / right end, compartments separated by "
       "`;`. Bulk density: coarse-grained mass over the bed height at the motion start. Surface speed: mean speed "
       "relative to the box in each column's surface cell, averaged over the columns and the frames of the motion "
       "(studies/ensemble_measures.hpp).\n\n"
       "| variant | seed | t start / end (s) | index start | index end | compartments at the end (left / right) | bulk "
       "density (kg/m^3) | bed height (mm) | surface speed (mm/s) | AOR (deg) |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& run : r.runs) {
    const RunMeasures& x = run.measures;
    m << "| " << run.variant << " | " << run.seed << " | " << g(x.t_start) << " / " << g(x.t_end) << " | "
      << g(x.index_start, 3) << " | " << g(x.index_end, 3) << " | " << compartments_cell(x, true) << " | "
      << g(x.bulk_density) << " | " << g(1e3 * x.bed_height, 3) << " | " << g(1e3 * x.surface_speed, 3) << " | "
      << (s.aor ? g(run.aor_deg, 3) : "not run") << " |\n";
  }
  m << "\n";

  m << "## Variants over seeds\n\nMean ± sample standard deviation over the seeds (n runs).\n\n| measure | unit |";
  for (const auto& v : s.variants) m << " " << v.label << " |";
  m << "\n|---|---|";
  for (std::size_t v = 0; v < nv; ++v) m << "---|";
  m << "\n";
  for (const auto& mc : c.measures) {
    m << "| " << mc.label << " | " << mc.unit << " |";
    for (const auto& st : mc.per_variant) m << " " << stats_cell(st) << " |";
    m << "\n";
  }
  if (!s.aor) m << "\nThe angle of repose was not run (the study file has no `aor` block).\n";
  m << "\n";

  m << "## Differences from the reference (" << ref_label << ")\n\n"
    << "Variant minus reference, with the Welch " << g(pct, 3)
    << " % interval (studies/welch_interval.hpp: unequal spreads, Welch-Satterthwaite degrees of freedom). "
       "\"differs\": the interval excludes zero, i.e. the variants differ by more than their seed spread allows.\n\n"
       "| measure | variant | difference [interval] | relative to the reference | differs? |\n|---|---|---|---|---|\n";
  for (const auto& mc : c.measures) {
    for (std::size_t v = 0; v < nv; ++v) {
      if (v == c.reference) continue;
      const WelchInterval& w = mc.vs_reference[v];
      const double base = mc.per_variant[c.reference].mean;
      m << "| " << mc.key << " | " << s.variants[v].label << " | " << interval_cell(w, pct) << " | "
        << (base != 0 && std::isfinite(base) ? g(100 * w.difference / base, 3) + " %" : "n/a") << " | "
        << (!w.defined ? "undefined" : w.excludes_zero ? "**differs**" : "no") << " |\n";
    }
  }
  m << "\n";

  m << "## Chaff per slice\n\n"
    << figure(out, "slices_end.png", "Chaff per 50 mm slice at the end, % of all chaff, mean over seeds (cf. the report's Figures 11 and 16-18)");
  for (const auto& v : s.variants) {
    m << figure(out, "slices_" + v.name + ".png", v.label + ": chaff per slice at the motion start and at the end");
  }
  m << figure(out, "relative_chaff.png", "Chaff field: each slice's chaff fraction over the box's at the end (1: uniform); dashed: ± one sd over seeds")
    << figure(out, "index.png", "Congregation index of every run at the end (circles) and at the motion start (crosses)")
    << "Chaff field compared with the reference: RMS over slices of the difference of the mean profiles over the RMS "
       "of its standard error (about 1 if only the seeds differ); \"differs\" above sqrt(chi^2_"
    << g(s.confidence, 3) << "(K)/K) for K slices (a screening threshold; with few seeds the errors are uncertain).\n\n"
       "| variant | RMS difference | RMS standard error | ratio | threshold | slices whose interval excludes 0 | differs? |\n"
       "|---|---|---|---|---|---|---|\n";
  for (std::size_t v = 0; v < nv; ++v) {
    if (v == c.reference) continue;
    m << "| " << s.variants[v].label << " | " << g(c.field.rms_difference[v], 3) << " | " << g(c.field.rms_error[v], 3)
      << " | " << g(c.field.ratio[v], 3) << " | " << g(c.field.threshold[v], 3) << " | " << c.field.slices_differing[v]
      << " of " << c.field.slice_lo.size() << " | " << (c.field.differs[v] ? "**differs**" : std::isfinite(c.field.ratio[v]) ? "no" : "undefined")
      << " |\n";
  }
  m << "\n";

  // The report's measurements.
  const MeasureComparison* idx = find(c, "index_end");
  m << "## Comparison with the report's measurements\n\n";
  {
    // The reference's right-hand 100 mm (the report's full-scale DEM: "more than double the percentage
    // of chaff particles ... in the right hand 100mm").
    double share = 0, length = 0;
    const double x_end = c.field.slice_hi.empty() ? 0 : c.field.slice_hi.back();
    for (std::size_t k = 0; k < c.field.slice_lo.size(); ++k) {
      if (c.field.slice_lo[k] >= x_end - 0.1 - 1e-9) {
        share += c.percent_end[c.reference][k].mean;
        length += c.field.slice_hi[k] - c.field.slice_lo[k];
      }
    }
    const double box = x_end - (c.field.slice_lo.empty() ? 0 : c.field.slice_lo.front());
    m << "| quantity | report | this study |\n|---|---|---|\n"
      << "| chaff in the right-hand 100 mm at the end, over the zone's length share (" << ref_label << ") | "
      << "\"more than double\" after 6.6 min at full scale (Figure 11) | "
      << (box > 0 && length > 0 ? g(share / 100 / (length / box), 3) : "n/a") << " after " << (r.runs.empty() ? "n/a" : g(r.runs.front().measures.t_end - s.motion_from, 3) + " s of motion")
      << " |\n";
    if (s.question == EnsembleQuestion::congregation) {
      for (std::size_t v = 0; v < nv; ++v) {
        if (v == c.reference) continue;
        m << "| congregation, " << s.variants[v].label << " against " << ref_label << " | \"the congregation of chaff "
          << "particles at the end has been reduced and the distribution of chaff is more uniform\" (split 2 x 400 mm, "
          << "no numbers) | index " << g(idx->per_variant[v].mean, 3) << " against " << g(idx->per_variant[c.reference].mean, 3)
          << " |\n";
      }
    } else {
      m << "| 1x against 2x | the report ran 2x because 1x took weeks; it did not compare them | the table above |\n";
    }
    m << "\n";
  }

  // Verdict.
  m << "## Verdict\n\n";
  if (s.question == EnsembleQuestion::congregation) {
    for (std::size_t v = 0; v < nv; ++v) {
      if (v == c.reference) continue;
      const WelchInterval& w = idx->vs_reference[v];
      const double a = idx->per_variant[c.reference].mean, b = idx->per_variant[v].mean;
      const double excess = a - 1;
      std::string how = "changes the congregation index from " + g(a, 3) + " (" + ref_label + ") to " + g(b, 3) + " (" +
                        s.variants[v].label + "), a difference of " + g(w.difference, 3);
      if (w.defined) how += " (" + g(pct, 3) + " % interval " + g(w.lo, 3) + " to " + g(w.hi, 3) + ")";
      if (excess > 0) how += ", i.e. " + g(-100 * w.difference / excess, 3) + " % of the reference's excess over a uniform mix removed";
      m << "Verdict: " << s.variants[v].label << " " << how << ". ";
      if (!w.defined) m << "With fewer than two seeds per variant there is no spread: no conclusion.";
      else if (w.hi < 0) m << "**Splitting reduces congregation**, by more than the seed spread allows (the report's reading).";
      else if (w.lo > 0) m << "**It increases congregation**, by more than the seed spread allows (against the report's reading).";
      else m << "**No difference detectable** over " << idx->per_variant[v].n << " and " << idx->per_variant[c.reference].n
             << " seeds: the difference lies within the seed spread.";
      m << "\n\n";
    }
  } else {
    std::vector<std::string> differ, agree, undefined;
    for (const auto& mc : c.measures) {
      for (std::size_t v = 0; v < nv; ++v) {
        if (v == c.reference) continue;
        const WelchInterval& w = mc.vs_reference[v];
        const std::string item = mc.key + (nv > 2 ? " (" + s.variants[v].label + ")" : "");
        (!w.defined ? undefined : w.excludes_zero ? differ : agree).push_back(item);
      }
    }
    for (std::size_t v = 0; v < nv; ++v) {
      if (v == c.reference) continue;
      const std::string item = std::string("chaff field") + (nv > 2 ? " (" + s.variants[v].label + ")" : "");
      (!std::isfinite(c.field.ratio[v]) ? undefined : c.field.differs[v] ? differ : agree).push_back(item);
    }
    auto list = [](const std::vector<std::string>& v) {
      std::string s;
      for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
      return s.empty() ? std::string("none") : s;
    };
    m << "Verdict: " << (differ.empty() ? (undefined.empty() ? "**the variants agree within the seed spread on every measure**"
                                                             : "**no difference found, but not every measure could be tested**")
                                        : "**the variants differ** in: " + list(differ))
      << ". Within the seed spread: " << list(agree) << ". Untested (fewer than two seeds or no data): " << list(undefined)
      << ". Agreement here means only that the difference is smaller than " << s.seeds.size()
      << " seeds can resolve; the table of differences gives its size.\n\n";
  }

  m << "## Limits\n\n"
    << "- Each run is one DEM realisation; the seeds change the random pour, so the spread is that of the packing "
       "and the chaff's starting places. " << s.seeds.size() << " seeds give wide intervals (the t quantile for 2 "
       "degrees of freedom is 4.3).\n"
    << "- The index counts bodies at their centres; with few chaff flakes per end zone it is noisy (counts per run in "
       "`runs.csv`).\n"
    << "- Runs shorter than the report's 1800 s show the start of the congregation, not its end state; the report "
       "itself drew its split-container conclusion from the pictures, without numbers.\n"
    << "- Particles at 2x (docs/scaling.md): containers and compartments narrower than ten particle sizes are flagged "
       "in the warnings; the scale_check study measures what 2x changes.\n";
  const std::string report = out + "/report.md";
  dem::write_file_atomically(report, m.str());
  return report;
}

}  // namespace grainscale::studies
