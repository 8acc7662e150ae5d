#include "studies/hold_output.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "continuum/field_output.hpp"
#include "continuum/observation.hpp"
#include "dem/atomic_file.hpp"
#include "studies/hold_measures.hpp"
#include "studies/plot.hpp"

namespace grainscale::studies {

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

HoldFiles write_hold_output(const HoldSettings& s, const HoldModel& model, const HoldResult& r) {
  HoldFiles out;
  out.folder = s.output_folder;
  std::filesystem::create_directories(out.folder);
  const auto path = [&](const std::string& name) {
    out.written.push_back(out.folder + "/" + name);
    return out.written.back();
  };
  const continuum::Grid& g = model.model().grid();
  const int nx = g.nx();

  {  // c(x, z, t) in the continuum layout
    continuum::SurfaceCoverage obs(150, s.friction.grain_diameter);
    continuum::RunRecord rec{r.times, r.fields};
    continuum::write_continuum_h5(path("continuum.h5"), model.model(), obs, rec);
  }
  std::ostringstream head;
  head << "time_s";
  for (int i = 0; i < nx; ++i) head << ",x_" << num(g.x_centre(i));
  head << "\n";

  // Surface concentration and closure surface over time.
  std::ostringstream sc, sh, ef;
  sc << "# chaff volume fraction in the top cell of each column (top " << num(s.window / s.nz) << " m)\n" << head.str();
  sh << "# bed depth h(x) from the flow closure [m]\n" << head.str();
  ef << "# share of the modelled chaff in the top " << num(s.top_layer) << " m within " << num(s.end_zone)
     << " m of each end wall\ntime_s,left,right,averaged_model\n";
  std::vector<double> heat, left, right;
  for (std::size_t j = 0; j < r.times.size(); ++j) {
    const auto surf = surface_concentration(g, r.fields[j]);
    sc << num(r.times[j]);
    sh << num(r.times[j]);
    for (int i = 0; i < nx; ++i) sc << "," << num(surf[i]), sh << "," << num(r.surface[j][i]);
    sc << "\n", sh << "\n";
    if (j > 0) heat.insert(heat.end(), surf.begin(), surf.end());
    const auto [l, rr] = end_top_fractions(g, r.fields[j], s.top_layer, s.end_zone);
    ef << num(r.times[j]) << "," << num(l) << "," << num(rr) << "," << r.averaged[j] << "\n";
    left.push_back(l), right.push_back(rr);
  }
  out.left_fraction = left.back(), out.right_fraction = right.back();
  dem::write_file_atomically(path("surface_chaff.csv"), sc.str());
  dem::write_file_atomically(path("surface.csv"), sh.str());
  dem::write_file_atomically(path("end_fractions.csv"), ef.str());

  const double hours = r.times.back() > 7200 ? 3600 : 1;
  const std::string tunit = hours > 1 ? "h" : "s";
  std::vector<double> tt;
  for (double t : r.times) tt.push_back(t / hours);
  std::vector<double> xe;
  for (int f = 0; f <= nx; ++f) xe.push_back(g.x_face(f));
  if (r.times.size() > 1) {
    HeatMap hm;
    hm.axes = {s.name + ": chaff at the surface", "x along the container [m]", "time [" + tunit + "]"};
    hm.x_edges = xe;
    hm.y_edges = tt;  // row j covers (t_j, t_{j+1}] and shows the field at t_{j+1}
    hm.values = heat;
    hm.value_label = "c (top cell)";
    draw(hm).write_png(path("surface_chaff.png"));
  }
  {
    LinePlot lp;
    lp.axes = {s.name + ": chaff in the top layer near the end walls", "time [" + tunit + "]", "share of all chaff"};
    lp.series.push_back({"left end", tt, left});
    lp.series.push_back({"right end", tt, right});
    draw(lp).write_png(path("end_fractions.png"));
  }
  {  // final c(x, depth below surface)
    HeatMap hm;
    hm.axes = {s.name + ": chaff at t = " + num(r.times.back() / hours) + " " + tunit, "x along the container [m]",
               "height in the top window [m]"};
    hm.x_edges = xe;
    for (int m = 0; m <= g.nz(); ++m) hm.y_edges.push_back(g.sigma_face(m) * g.h_column(0) - s.window);
    hm.values.resize(static_cast<std::size_t>(nx) * g.nz());
    for (int i = 0; i < nx; ++i) {
      for (int k = 0; k < g.nz(); ++k) hm.values[static_cast<std::size_t>(k) * nx + i] = r.fields.back()[g.index(i, k)];
    }
    hm.value_label = "c";
    draw(hm).write_png(path("chaff_map.png"));
  }
  {  // spear samples at the end
    const auto spear = spear_profile(g, r.fields.back(), s.spear_depth, s.chaff_initial);
    const double dirty = s.dirty_factor * s.chaff_initial;
    std::ostringstream sp;
    sp << "# mean chaff fraction a spear of " << num(s.spear_depth) << " m pushed in at x collects (t = "
       << num(r.times.back()) << " s); dirty: above " << num(s.dirty_factor) << " x the initial " << num(s.chaff_initial)
       << "\nx_m,spear_mean,dirty\n";
    std::vector<double> xc, th;
    bool in = false;
    for (int i = 0; i < nx; ++i) {
      const bool d = spear[i] > dirty;
      sp << num(g.x_centre(i)) << "," << num(spear[i]) << "," << (d ? 1 : 0) << "\n";
      if (d && !in) out.dirty_from.push_back(g.x_face(i));
      if (!d && in) out.dirty_to.push_back(g.x_face(i));
      in = d;
      xc.push_back(g.x_centre(i)), th.push_back(dirty);
    }
    if (in) out.dirty_to.push_back(g.length());
    dem::write_file_atomically(path("spear.csv"), sp.str());
    LinePlot lp;
    lp.axes = {s.name + ": what a " + num(s.spear_depth) + " m spear finds", "x along the container [m]",
               "mean chaff fraction"};
    lp.axes.y_min = 0;
    lp.series.push_back({"spear sample", xc, spear});
    Series thr{"dirty above", xc, th};
    thr.line = LineStyle::dashed;
    lp.series.push_back(thr);
    draw(lp).write_png(path("spear.png"));
  }
  {  // closure surface, start and end
    LinePlot lp;
    lp.axes = {s.name + ": bed depth from the flow closure", "x along the container [m]", "h [m]"};
    std::vector<double> xc;
    for (int i = 0; i < nx; ++i) xc.push_back(g.x_centre(i));
    lp.series.push_back({"t = 0", xc, r.surface.front()});
    lp.series.push_back({"end", xc, r.surface.back()});
    draw(lp).write_png(path("surface.png"));
  }
  {
    std::ostringstream y;
    y << "# grainscale hold run summary\nname: " << s.name << "\nsimulated_time_s: " << num(r.times.back())
      << "\nresolved_cycles: " << r.resolved_chunks << "\ncycle_s: " << num(s.chunk)
      << "\naveraged_model_used: " << (r.averaged.back() ? "true" : "false") << "\nclosure_steps: " << r.closure_steps
      << "\nchaff_steps: " << r.chaff_steps;
    if (r.averaged.back()) {
      y << "\naveraged_model: {integrator: " << r.averaged_integrator << ", steps: " << r.averaged_steps
        << ", wall_clock_s: " << num(r.averaged_wall_seconds) << ", stiffest_rate_per_s: " << num(r.averaged_max_rate) << "}";
    }
    y << "\nwall_clock_s: " << num(r.wall_seconds)
      << "\nchaff_initial_m2: " << num(r.chaff_initial) << "\nchaff_final_m2: " << num(r.chaff_final)
      << "\nchaff_relative_change: " << num(r.chaff_initial > 0 ? (r.chaff_final - r.chaff_initial) / r.chaff_initial : 0)
      << "\nc_range: [" << num(r.c_min) << ", " << num(r.c_max) << "]\nend_top_fraction_left: " << num(out.left_fraction)
      << "\nend_top_fraction_right: " << num(out.right_fraction) << "\ndirty_intervals_m: [";
    for (std::size_t k = 0; k < out.dirty_from.size(); ++k) {
      y << (k ? ", " : "") << "[" << num(out.dirty_from[k]) << ", " << num(out.dirty_to[k]) << "]";
    }
    y << "]\n";
    dem::write_file_atomically(path("summary.yaml"), y.str());
  }
  return out;
}

}  // namespace grainscale::studies
