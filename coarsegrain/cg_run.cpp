#include "coarsegrain/cg_run.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <sstream>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/csv_table.hpp"
#include "coarsegrain/field_file.hpp"
#include "coarsegrain/moments.hpp"
#include "coarsegrain/phase_average.hpp"
#include "coarsegrain/slice_histogram.hpp"
#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"
#include "grainscale_version.hpp"

namespace grainscale::cg {

namespace {

namespace fs = std::filesystem;

SpeciesTable species_table(const dem::Snapshot& first, const CgSettings& s) {
  SpeciesTable t = species_from_snapshot(first, s.chaff);
  t.density = s.density;
  return t;
}

/// The true particle diameter the kernel width is measured in: from the settings, or the mean sphere
/// diameter of the reference species in the first snapshot divided by its scale factor.
double true_diameter(const dem::Snapshot& snap, const SpeciesTable& species, const CgSettings& s) {
  if (s.true_diameter > 0) return s.true_diameter;
  const int ref = s.diameter_species.empty() ? -1 : species.index(s.diameter_species);
  if (!s.diameter_species.empty() && ref < 0) {
    throw InputError(s.source + ": kernel.diameter_of = '" + s.diameter_species + "' is not a material of " + s.snapshots.front().path);
  }
  bool any_grain = false;
  for (std::size_t k = 0; k < species.chaff.size(); ++k) any_grain = any_grain || !species.chaff[k];
  double sum = 0;
  long n = 0;
  for (std::size_t k = 0; k < snap.radius.size(); ++k) {
    const int sp = species.index(snap.material_names[static_cast<std::size_t>(snap.material[k])]);
    const bool use = ref >= 0 ? sp == ref : (!any_grain || !species.chaff[static_cast<std::size_t>(sp)]);
    if (!use) continue;
    sum += 2 * snap.radius[k];
    ++n;
  }
  if (n == 0) {
    throw InputError(s.source + ": cannot take the kernel's reference diameter from " + s.snapshots.front().path +
                     " (no particles of the reference species); set kernel.diameter");
  }
  return sum / static_cast<double>(n) / snap.scale_factor;
}

/// |integral of the mixture density - mass of the particles inside the box| / that mass.
double mass_error(const Moments& m, const CgParticles& p, const Grid& grid) {
  double total = 0, inside = 0;
  for (std::size_t c = 0; c < m.cells; ++c) total += m.mass[m.at(m.mixture(), c)] * grid.cell_volume();
  for (std::size_t k = 0; k < p.size(); ++k)
    if (grid.contains(p.position[k])) inside += p.mass[k];
  return inside > 0 ? std::abs(total - inside) / inside : 0.0;
}

void add_field_rows(CsvTable& csv, const Fields& f) {
  const Grid& g = f.grid;
  for (int k = 0; k < g.cells[2]; ++k)
    for (int j = 0; j < g.cells[1]; ++j)
      for (int i = 0; i < g.cells[0]; ++i) {
        const std::size_t c = g.index(i, j, k);
        const auto& u = f.mixture.velocity[c];
        const auto& flux = f.segregation_flux[c];
        csv.row({f.time, g.centre(0, i), g.centre(2, k), f.chaff_volume_concentration[c], g.centre(1, j), f.mixture.volume_fraction[c],
                 f.mixture.density[c], u.x, u.y, u.z, f.shear_rate[c], f.mixture.temperature[c], f.chaff_number_concentration[c],
                 flux.x, flux.y, flux.z});
      }
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return std::isnan(v) ? ".nan" : s.str();
}

/// Mean and sample standard deviation of the finite values.
std::pair<double, double> mean_std(const std::vector<double>& v) {
  double sum = 0, n = 0;
  for (double x : v)
    if (std::isfinite(x)) sum += x, n += 1;
  if (n == 0) return {std::nan(""), std::nan("")};
  const double mean = sum / n;
  double ss = 0;
  for (double x : v)
    if (std::isfinite(x)) ss += (x - mean) * (x - mean);
  return {mean, n > 1 ? std::sqrt(ss / (n - 1)) : 0.0};
}

}  // namespace

/// Motion phase the DEM recorded for the container wall (docs/snapshot_layout.md, `motion_phase`).
static double recorded_phase(const dem::Snapshot& snap, const std::string& wall, const std::string& path) {
  for (const dem::WallPoseRecord& w : snap.walls) {
    if (w.name == wall && w.moving) return w.motion_phase;
  }
  throw InputError(path + ": phase averaging needs a 'phase' per snapshot, 'averaging.period', or a container wall "
                   "with a prescribed motion; wall '" + wall + "' " +
                   (wall.empty() ? std::string("is not set") : "does not move in this snapshot"));
}

/// Snapshots in one whole cycle of `period`: the period over the median interval between the
/// (sorted) snapshot times, rounded; 1 for a single snapshot.
static int snapshots_per_cycle(std::vector<double> times, double period) {
  std::sort(times.begin(), times.end());
  std::vector<double> gaps;
  for (std::size_t k = 1; k < times.size(); ++k)
    if (times[k] > times[k - 1]) gaps.push_back(times[k] - times[k - 1]);
  if (gaps.empty()) return 1;
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  return std::max(1, static_cast<int>(std::lround(period / gaps[gaps.size() / 2])));
}

CgSummary run_coarse_graining(const CgSettings& s) {
  if (s.snapshots.empty()) throw InputError(s.source + ": no snapshots to coarse-grain");
  std::error_code ec;
  fs::create_directories(s.output_dir, ec);
  if (ec) throw std::runtime_error("cannot create output folder " + s.output_dir + ": " + ec.message());

  const dem::Snapshot first = dem::read_snapshot(s.snapshots.front().path);
  const SpeciesTable species = species_table(first, s);
  CgSummary summary;
  summary.output_dir = s.output_dir;
  summary.true_diameter = true_diameter(first, species, s);
  summary.warnings = clump_volume_warnings(first, species, s.source);
  summary.kernel_width = kernel_width_m(s.width_diameters, summary.true_diameter);
  const Kernel kernel{s.kernel, summary.kernel_width, s.boundary};
  const Grid grid = Grid::make(s.dimension, s.lo, s.hi, s.cells);
  const Slices slices(s.lo.x, s.hi.x, s.slice_width);

  CsvTable slices_csv({"t_s", "x_m", "chaff_percent", "x_lo_m", "x_hi_m", "chaff_bodies", "grain_bodies", "c_number", "c_volume"});
  CsvTable coverage_csv({"t_s", "x_m", "coverage", "x_lo_m", "x_hi_m", "occupied_pixels", "chaff_pixels"});
  CsvTable congregation_csv({"t_s", "index_left", "index_right", "index_mean", "index_spread", "share_left", "share_right",
                             "coverage_left", "coverage_centre", "coverage_right", "coverage_ratio", "coverage"});

  std::vector<FieldFrame> frames;
  Moments window;
  PhaseAverage phases(s.averaging == Averaging::phase ? s.phase_bins : 1);
  std::map<long, Moments> cycles;  // cycle index k -> the sum over its snapshots
  std::vector<std::string> used;   // the snapshots in [from, to]
  const FieldOptions& options = s.surface;

  for (std::size_t n = 0; n < s.snapshots.size(); ++n) {
    const dem::Snapshot snap = n == 0 ? first : dem::read_snapshot(s.snapshots[n].path);
    // averaging.from/to: a time range of the run (the motion, not the pour), to round-off in the
    // snapshots' times.
    const double slack = 1e-9 * std::max(1.0, std::abs(snap.time));
    if (snap.time < s.from - slack || snap.time > s.to + slack) continue;
    used.push_back(s.snapshots[n].path);
    const CgParticles p = container_particles(snap, container_pose(snap, s.container_wall), species);
    const Moments m = coarse_grain(p, species.size(), grid, kernel);
    summary.max_mass_error = std::max(summary.max_mass_error, mass_error(m, p, grid));
    summary.times.push_back(snap.time);
    switch (s.averaging) {
      case Averaging::snapshot: frames.push_back({derive_fields(m, grid, species, options), "snapshot", 0, 0}); break;
      case Averaging::window: window.add(m); break;
      case Averaging::phase: {
        // The snapshot's own phase (settings), else from the time and period, else the phase the
        // DEM recorded for the container wall's motion.
        double phase = s.snapshots[n].phase;
        if (std::isnan(phase) && s.period > 0) phase = (snap.time - s.t0) / s.period;
        if (std::isnan(phase)) phase = recorded_phase(snap, s.container_wall, s.snapshots[n].path);
        phases.add(phase, m);
        break;
      }
      case Averaging::cycles: {
        // Cycle k is [t0 + kT, t0 + (k + 1)T); a snapshot on a boundary opens the next cycle, also
        // when it is up to 0.1 % of a cycle early (the DEM writes a snapshot at a step near its
        // time, not at it). Snapshots before t0 belong to no cycle.
        const double k = std::floor((snap.time - s.t0) / s.period + 1e-3);
        if (k < 0) break;
        auto [it, fresh] = cycles.try_emplace(static_cast<long>(k), m);
        if (!fresh) it->second.add(m);
        break;
      }
    }

    const SliceHistogram h = slice_histogram(p, species, slices);
    for (int k = 0; k < slices.count(); ++k) {
      const auto q = static_cast<std::size_t>(k);
      slices_csv.row({snap.time, slices.centre(k), h.chaff_percent[q], slices.lower(k), slices.upper(k), h.chaff_bodies[q], h.grain_bodies[q],
                      h.chaff_number_fraction[q], h.chaff_volume_fraction[q]});
    }
    const TopView view = render_top_view(p, species, s.lo, s.hi, s.top_view);
    const CoverageProfile cov = coverage_profile(view, slices);
    for (int k = 0; k < slices.count(); ++k) {
      const auto q = static_cast<std::size_t>(k);
      coverage_csv.row({snap.time, slices.centre(k), cov.coverage[q], slices.lower(k), slices.upper(k),
                        static_cast<double>(cov.occupied_pixels[q]), static_cast<double>(cov.chaff_pixels[q])});
    }
    const CongregationIndex ci = congregation_index(p, species, s.lo.x, s.hi.x, s.end_length, &view);
    summary.congregation.push_back(ci);
    congregation_csv.row({snap.time, ci.left, ci.right, ci.mean, ci.spread, ci.share_left, ci.share_right, ci.coverage_left,
                          ci.coverage_centre, ci.coverage_right, ci.coverage_ratio, view.coverage()});
  }
  if (summary.times.empty()) {
    throw InputError(s.source + ": averaging.from/to: no snapshot lies in [" + std::to_string(s.from) + ", " + std::to_string(s.to) + "] s");
  }
  if (s.averaging == Averaging::window) {
    window.average();
    frames.push_back({derive_fields(window, grid, species, options), "window", 0, 0});
  } else if (s.averaging == Averaging::phase) {
    for (int b = 0; b < phases.bins(); ++b) {
      if (phases.count(b) == 0) continue;  // no snapshot at this phase
      frames.push_back({derive_fields(phases.average(b), grid, species, options), "phase", static_cast<double>(b) / phases.bins(),
                        static_cast<double>(b + 1) / phases.bins()});
    }
  } else if (s.averaging == Averaging::cycles) {
    // Only whole cycles: as many snapshots as the period holds at the usual snapshot interval, so
    // that each frame is a cycle mean, not a part of one weighted toward some phases.
    const int full = snapshots_per_cycle(summary.times, s.period);
    for (auto& [k, sum] : cycles) {
      if (sum.snapshots < full) continue;
      sum.average();
      frames.push_back({derive_fields(sum, grid, species, options), "cycles", 0, 0});
    }
    if (frames.empty()) {
      throw InputError(s.source + ": averaging.period = " + std::to_string(s.period) + " s, t0 = " + std::to_string(s.t0) +
                       " s: no whole cycle of " + std::to_string(full) + " snapshots among the " +
                       std::to_string(s.snapshots.size()) + " given");
    }
  }
  summary.snapshots = static_cast<int>(summary.times.size());
  summary.frames = static_cast<int>(frames.size());

  FieldFileInfo info;
  info.kernel = kernel;
  info.width_diameters = s.width_diameters;
  info.true_diameter = summary.true_diameter;
  info.scale_factor = first.scale_factor;
  info.container_wall = s.container_wall;
  info.chaff_species = s.chaff;
  info.snapshots = used;
  info.max_mass_error = summary.max_mass_error;
  const fs::path out(s.output_dir);
  write_field_file((out / "fields.h5").string(), frames, info);
  write_field_xdmf((out / "fields.xmf").string(), "fields.h5", frames);
  CsvTable fields_csv({"t_s", "x_m", "z_m", "c", "y_m", "phi", "rho_kg_m3", "u_x", "u_y", "u_z", "shear_rate_1_s", "temperature_m2_s2",
                       "c_number", "flux_x", "flux_y", "flux_z"});
  for (const auto& f : frames) add_field_rows(fields_csv, f.fields);
  fields_csv.write((out / "fields.csv").string());
  slices_csv.write((out / "slices.csv").string());
  coverage_csv.write((out / "coverage.csv").string());
  congregation_csv.write((out / "congregation.csv").string());

  // summary.yaml: what was done, and the congregation statistics over the snapshots beside the
  // report's measured values.
  std::vector<double> idx, ratio;
  for (const auto& c : summary.congregation) idx.push_back(c.mean), ratio.push_back(c.coverage_ratio);
  const auto [idx_mean, idx_std] = mean_std(idx);
  const auto [ratio_mean, ratio_std] = mean_std(ratio);
  const CongregationIndex& a = summary.congregation.front();
  const CongregationIndex& b = summary.congregation.back();
  std::ostringstream y;
  y << "# grainscale cg summary (" << grainscale::version << " " << grainscale::git_revision << ")\n"
    << "settings: " << s.source << "\n"
    << "snapshots: " << summary.snapshots << "\nframes: " << summary.frames << "\naveraging: " << name(s.averaging) << "\n"
    << "kernel: {type: " << name(s.kernel) << ", boundary: " << name(s.boundary) << ", width_diameters: " << number(s.width_diameters)
    << ", true_diameter_m: " << number(summary.true_diameter) << ", width_m: " << number(summary.kernel_width)
    << ", cutoff_m: " << number(kernel.cutoff()) << "}\n"
    << "max_mass_error: " << number(summary.max_mass_error) << "   # |sum rho V - M| / M, worst snapshot\n"
    << "congregation:\n"
    << "  index_mean_over_snapshots: {mean: " << number(idx_mean) << ", std: " << number(idx_std) << "}\n"
    << "  coverage_ratio_over_snapshots: {mean: " << number(ratio_mean) << ", std: " << number(ratio_std) << "}\n"
    << "  initial: {t_s: " << number(summary.times.front()) << ", index_left: " << number(a.left) << ", index_right: " << number(a.right)
    << ", coverage_centre: " << number(a.coverage_centre) << ", coverage_ends: " << number(0.5 * (a.coverage_left + a.coverage_right)) << "}\n"
    << "  final: {t_s: " << number(summary.times.back()) << ", index_left: " << number(b.left) << ", index_right: " << number(b.right)
    << ", coverage_centre: " << number(b.coverage_centre) << ", coverage_ends: " << number(0.5 * (b.coverage_left + b.coverage_right)) << "}\n"
    << "  report_wheat_photographs: {coverage_centre: 0.10, coverage_ends: 0.60, coverage_ratio: 6.0}   # SAGIT USA120, after 30 min\n";
  dem::write_file_atomically((out / "summary.yaml").string(), y.str());
  return summary;
}

}  // namespace grainscale::cg
