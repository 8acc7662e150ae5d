#include "studies/ensemble_measures.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "coarsegrain/cg_particles.hpp"
#include "coarsegrain/congregation_index.hpp"
#include "coarsegrain/container_frame.hpp"
#include "coarsegrain/slice_histogram.hpp"
#include "dem/input_error.hpp"
#include "dem/snapshot.hpp"
#include "studies/numeric_csv.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Snapshots of a run, in name (= time) order.
std::vector<std::string> snapshot_files(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() == ".h5") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

struct Frame {
  cg::CgParticles particles;
  cg::SpeciesTable species;
};

Frame frame_of(const dem::Snapshot& snap, const cg::CgSettings& cg) {
  Frame f;
  f.species = cg::species_from_snapshot(snap, cg.chaff);
  f.species.density = cg.density;
  f.particles = cg::container_particles(snap, cg::container_pose(snap, cg.container_wall), f.species);
  return f;
}

/// One column of a 2-D coarse-grained frame: solid fraction, density and velocity by height.
struct Column {
  std::vector<double> z, phi, rho, ux, uz;
};

/// The free surface of a column (see the header) and the index of its surface cell; -1 if empty.
int surface_cell(const Column& c, double dz, double z_top, double* height) {
  double peak = 0;
  for (double p : c.phi) peak = std::max(peak, std::isfinite(p) ? p : 0.0);
  if (peak < 0.05) return -1;  // no bed here (a few stray grains)
  const double half = 0.5 * peak;
  int k = -1;
  for (int i = 0; i < static_cast<int>(c.phi.size()); ++i) {
    if (c.phi[i] >= half) k = i;
  }
  if (k + 1 < static_cast<int>(c.phi.size())) {
    const double above = std::isfinite(c.phi[k + 1]) ? c.phi[k + 1] : 0.0;
    *height = c.z[k] + (c.phi[k] - half) / std::max(c.phi[k] - above, 1e-300) * dz;
  } else {
    *height = z_top;
  }
  return k;
}

}  // namespace

std::vector<CompartmentIndex> equal_compartments(double x_lo, double x_hi, int count) {
  std::vector<CompartmentIndex> out(static_cast<std::size_t>(std::max(count, 1)));
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k].x_lo = x_lo + (x_hi - x_lo) * k / out.size();
    out[k].x_hi = x_lo + (x_hi - x_lo) * (k + 1) / out.size();
  }
  return out;
}

std::vector<CompartmentIndex> scenario_compartments(const std::string& scenario_file, const std::string& wall,
                                                    double x_lo, double x_hi) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(scenario_file);
  } catch (const YAML::Exception& e) {
    throw InputError(scenario_file + ": " + e.what());
  }
  for (const auto& w : root["walls"]) {
    if (!w.IsMap() || !w["name"] || w["name"].as<std::string>() != wall) continue;
    if (!w["type"] || w["type"].as<std::string>() != "box_mesh") break;
    const int n = w["compartments"] ? w["compartments"].as<int>() : 1;
    return equal_compartments(w["min"][0].as<double>(), w["max"][0].as<double>(), n);
  }
  return equal_compartments(x_lo, x_hi, 1);
}

RunMeasures measure_run(const std::string& snapshot_dir, const cg::CgSettings& cg, const std::string& cg_output,
                        double motion_from, std::vector<CompartmentIndex> compartments) {
  RunMeasures r;
  r.compartments = std::move(compartments);
  const std::vector<std::string> files = snapshot_files(snapshot_dir);
  if (files.empty()) throw InputError(snapshot_dir + ": no snapshots (*.h5)");
  std::vector<double> times;
  for (const auto& f : files) times.push_back(dem::read_snapshot(f).time);
  // Snapshots fall on the first step at or after their time: allow a step's slack (1 % of a gap).
  const double slack = times.size() > 1 ? 0.01 * (times[1] - times[0]) : 0;
  std::size_t k0 = 0;
  while (k0 < times.size() && times[k0] < motion_from - slack) ++k0;
  if (k0 == times.size()) {
    throw InputError(snapshot_dir + ": no snapshot at or after the motion start (cg.motion_from = " +
                     std::to_string(motion_from) + " s); the last is at " + std::to_string(times.back()) + " s");
  }
  r.t_start = times[k0];
  r.t_end = times.back();

  // Particle measures: the index per compartment and chaff per slice, at the start and the end.
  const cg::Slices slices(cg.lo.x, cg.hi.x, cg.slice_width);
  for (int pass = 0; pass < 2; ++pass) {
    const dem::Snapshot snap = dem::read_snapshot(pass == 0 ? files[k0] : files.back());
    const Frame f = frame_of(snap, cg);
    double sum = 0;
    for (CompartmentIndex& c : r.compartments) {
      const double end = std::min(cg.end_length, 0.5 * (c.x_hi - c.x_lo));
      const cg::CongregationIndex ci = cg::congregation_index(f.particles, f.species, c.x_lo, c.x_hi, end, nullptr);
      (pass == 0 ? c.left_start : c.left_end) = ci.left;
      (pass == 0 ? c.right_start : c.right_end) = ci.right;
      sum += ci.mean;
    }
    (pass == 0 ? r.index_start : r.index_end) = sum / static_cast<double>(r.compartments.size());
    const cg::SliceHistogram h = cg::slice_histogram(f.particles, f.species, slices);
    (pass == 0 ? r.chaff_percent_start : r.chaff_percent_end) = h.chaff_percent;
    if (pass == 1) {
      r.grain_bodies = static_cast<int>(h.grain_total);
      r.chaff_bodies = static_cast<int>(h.chaff_total);
      const double all = h.chaff_total + h.grain_total;
      const double c_box = all > 0 ? h.chaff_total / all : kNaN;
      for (int s = 0; s < slices.count(); ++s) {
        r.slice_lo.push_back(slices.lower(s));
        r.slice_hi.push_back(slices.upper(s));
        r.relative_chaff_end.push_back(c_box > 0 ? h.chaff_number_fraction[s] / c_box : kNaN);
      }
    }
  }

  // Field measures from the coarse-grained frames (fields.csv: x fastest, then z).
  const NumericCsv fields = NumericCsv::load(cg_output + "/fields.csv");
  const std::vector<double> t = fields.column("t_s"), x = fields.column("x_m"), z = fields.column("z_m"),
                            phi = fields.column("phi"), rho = fields.column("rho_kg_m3"), ux = fields.column("u_x"),
                            uz = fields.column("u_z");
  std::map<double, std::map<double, Column>> frames;  // t -> x -> column (z ascending as written)
  for (std::size_t i = 0; i < fields.rows(); ++i) {
    Column& c = frames[t[i]][x[i]];
    c.z.push_back(z[i]), c.phi.push_back(phi[i]), c.rho.push_back(rho[i]), c.ux.push_back(ux[i]), c.uz.push_back(uz[i]);
  }
  const double dz = (cg.hi.z - cg.lo.z) / cg.cells[2];
  double speed_sum = 0;
  bool have_start = false;
  for (const auto& [time, columns] : frames) {
    if (!have_start && time >= r.t_start - slack) {
      // Bulk density of the settled bed at the motion start.
      have_start = true;
      double mass = 0, height = 0;
      int n = 0;
      for (const auto& [xc, col] : columns) {
        double h = 0;
        if (surface_cell(col, dz, cg.hi.z, &h) < 0) continue;
        for (double v : col.rho) mass += std::isfinite(v) ? v * dz : 0.0;
        height += h - cg.lo.z;
        ++n;
      }
      r.bulk_density = height > 0 ? mass / height : kNaN;
      r.bed_height = n > 0 ? height / n : kNaN;
      continue;
    }
    if (!have_start) continue;
    double sum = 0;
    int n = 0;
    for (const auto& [xc, col] : columns) {
      double h = 0;
      const int k = surface_cell(col, dz, cg.hi.z, &h);
      if (k < 0 || !std::isfinite(col.ux[k]) || !std::isfinite(col.uz[k])) continue;
      sum += std::hypot(col.ux[k], col.uz[k]);
      ++n;
    }
    if (n > 0) speed_sum += sum / n, ++r.motion_frames;
  }
  if (!have_start) r.bulk_density = r.bed_height = kNaN;
  r.surface_speed = r.motion_frames > 0 ? speed_sum / r.motion_frames : kNaN;
  return r;
}

}  // namespace grainscale::studies
