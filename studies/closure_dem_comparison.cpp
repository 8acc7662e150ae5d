#include "studies/closure_dem_comparison.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "continuum/closure/shallow_granular_flow.hpp"
#include "dem/atomic_file.hpp"
#include "dem/hdf5_numbers.hpp"
#include "dem/input_error.hpp"
#include "dem/material.hpp"
#include "dem/scenario.hpp"
#include "studies/plot.hpp"

namespace grainscale::studies {

namespace fs = std::filesystem;
using continuum::closure::BedFriction;

namespace {

/// One coarse-grained frame on an (x, z) grid, averaged over y.
struct DemFrame {
  double t = 0;
  std::vector<double> h;            // surface height per column (NaN: no grain) [m]
  std::vector<double> ux, density;  // [k * nx + i]
};

struct DemFields {
  std::vector<double> x, z;  // cell centres in the container frame
  double lo_x = 0, hi_x = 0, lo_z = 0, width = 0;  // width: the box across the section (y) [m]
  std::vector<DemFrame> frames;
};

DemFields read_dem_fields(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw InputError(path + ": cannot open as HDF5");
  DemFields d;
  try {
    if (H5Aexists(file, "cg_layout_version") <= 0) throw InputError(path + ": not a grainscale cg field file (no cg_layout_version)");
    std::vector<hsize_t> dx, dy, dz, dims;
    d.x = dem::read_hdf5_doubles(file, path, "/grid/x", dx);
    const auto y = dem::read_hdf5_doubles(file, path, "/grid/y", dy);
    d.z = dem::read_hdf5_doubles(file, path, "/grid/z", dz);
    const auto lo = dem::read_hdf5_attribute(file, path, "/grid", "lo", 3), hi = dem::read_hdf5_attribute(file, path, "/grid", "hi", 3);
    d.lo_x = lo[0], d.hi_x = hi[0], d.lo_z = lo[2], d.width = hi[1] - lo[1];
    const std::size_t nx = d.x.size(), ny = y.size(), nz = d.z.size();
    if (nz < 2 || nx < 3) throw InputError(path + ": needs an (x, z) grid (2-D or 3-D) with at least 3 x and 2 z cells");
    const int frames = static_cast<int>(dem::read_hdf5_attribute(file, path, "/frames", "count", 1)[0]);
    for (int f = 0; f < frames; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "/frames/%06d", f);
      DemFrame fr;
      fr.t = dem::read_hdf5_attribute(file, path, name, "time", 1)[0];
      const auto h = dem::read_hdf5_doubles(file, path, std::string(name) + "/surface_height", dims);
      if (h.size() != ny * nx) throw InputError(path + ": " + name + "/surface_height is not (ny, nx)");
      const auto u = dem::read_hdf5_doubles(file, path, std::string(name) + "/mixture/velocity", dims);
      const auto rho = dem::read_hdf5_doubles(file, path, std::string(name) + "/mixture/density", dims);
      if (u.size() != nz * ny * nx * 3 || rho.size() != nz * ny * nx) {
        throw InputError(path + ": " + name + "/mixture/velocity or density is not (nz, ny, nx[, 3])");
      }
      fr.h.assign(nx, NAN);
      fr.ux.assign(nz * nx, NAN);
      fr.density.assign(nz * nx, 0.0);
      for (std::size_t i = 0; i < nx; ++i) {
        double hs = 0;
        int hn = 0;
        for (std::size_t j = 0; j < ny; ++j) {
          if (std::isfinite(h[j * nx + i])) hs += h[j * nx + i], ++hn;
        }
        if (hn) fr.h[i] = hs / hn;
        for (std::size_t k = 0; k < nz; ++k) {
          double m = 0, p = 0;  // mass-weighted over y
          for (std::size_t j = 0; j < ny; ++j) {
            const std::size_t c = (k * ny + j) * nx + i;
            if (rho[c] > 0 && std::isfinite(u[3 * c])) m += rho[c], p += rho[c] * u[3 * c];
          }
          fr.density[k * nx + i] = m / ny;
          if (m > 0) fr.ux[k * nx + i] = p / m;
        }
      }
      d.frames.push_back(std::move(fr));
    }
    H5Fclose(file);
  } catch (...) {
    H5Fclose(file);
    throw;
  }
  return d;
}

/// Least-squares slope of h over x where h > h_min (NaN if fewer than 3 such columns).
double slope(const std::vector<double>& x, const std::vector<double>& h, double h_min) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(h[i] > h_min)) continue;
    sx += x[i], sy += h[i], sxx += x[i] * x[i], sxy += x[i] * h[i], ++n;
  }
  if (n < 3) return NAN;
  const double den = n * sxx - sx * sx;
  return den > 0 ? (n * sxy - sx * sy) / den : NAN;
}

void rms_max(const std::vector<double>& a, const std::vector<double>& b, double& rms, double& mx) {
  double s = 0;
  int n = 0;
  mx = 0;
  for (std::size_t j = 0; j < a.size(); ++j) {
    if (!std::isfinite(a[j]) || !std::isfinite(b[j])) continue;
    s += (a[j] - b[j]) * (a[j] - b[j]), ++n;
    mx = std::max(mx, std::fabs(a[j] - b[j]));
  }
  rms = n ? std::sqrt(s / n) : NAN;
  if (!n) mx = NAN;
}

/// The fitted closure's series and a vertical line at the end of the training frames, spanning `range`'s values.
void add_fit_series(LinePlot& lp, const ClosureFit& fit, const std::vector<double>& t, const std::vector<double>& y,
                    const std::vector<double>& range) {
  char name[64];
  std::snprintf(name, sizeof name, "closure fitted to t <= %g s", fit.settings.train_until);
  lp.series.push_back({name, t, y});
  double lo = 0, hi = 0;
  for (double v : range) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  Series split{"end of training frames", {fit.settings.train_until, fit.settings.train_until}, {lo, hi}};
  split.line = LineStyle::dashed;
  split.width = 1;
  lp.series.push_back(split);
}

}  // namespace

ClosureDemComparison compare_closure_with_dem(const std::string& cg_fields, const std::string& dem_scenario,
                                              const std::string& container, const HoldSettings& material,
                                              const std::string& folder, const std::optional<ClosureFitSettings>& fit,
                                              double measure_depth) {
  ClosureDemComparison out;
  out.cg_fields = cg_fields, out.dem_scenario = dem_scenario, out.material_from = material.name;
  const DemFields dem = read_dem_fields(cg_fields);

  // The container and its motion, from the DEM scenario.
  const dem::Scenario sc = dem::load_scenario(dem_scenario);
  const dem::WallSpec* wall = nullptr;
  for (const auto& w : sc.walls) {
    if (container.empty() ? w.motion.profile != nullptr : w.name == container) {
      wall = &w;
      break;
    }
  }
  if (!wall || !wall->motion.profile) {
    throw InputError(dem_scenario + ": " + (container.empty() ? std::string("no moving wall (the container's motion is needed)")
                                                              : "no moving wall named '" + container + "'"));
  }
  if (std::fabs(std::fabs(wall->pose.orientation.w) - 1) > 1e-9) {
    throw InputError(dem_scenario + ": wall '" + wall->name + "' is rotated at rest; the comparison needs a box aligned with the world axes");
  }
  BedFriction friction = material.friction;
  out.box_length = dem.hi_x - dem.lo_x;
  out.flowing_layer = friction.layer_depth;
  const double d = friction.grain_diameter, h_min = 0.5 * d;
  const int nx = static_cast<int>(dem.x.size());

  continuum::closure::ContainerPlacement p;
  p.origin = wall->pose.origin + dem::Vec3{dem.lo_x, 0, dem.lo_z};
  p.pivot = wall->motion.pivot;
  const continuum::closure::ContainerGravity gravity(wall->motion.profile, p);
  auto at_rest = [&](double t) {
    const dem::RigidMotionState st = gravity.state(t);
    return std::fabs(gravity.tilt(st)) < 1e-9 && dot(st.angular_velocity, st.angular_velocity) < 1e-18;
  };
  // Compare from the last frame at rest before the motion starts (the closure's initial state).
  std::size_t first = 0;
  while (first + 1 < dem.frames.size() && at_rest(dem.frames[first + 1].t)) ++first;
  if (dem.frames.size() - first < 2) throw InputError(cg_fields + ": fewer than 2 frames from the start of the motion");

  // The closure from the DEM's bed at that frame (columns interpolated onto the closure's cells).
  std::vector<double> h0(nx, 0.0), xc(nx);
  double fill = 0;
  for (int i = 0; i < nx; ++i) {
    xc[i] = dem.x[i] - dem.lo_x;
    const double h = dem.frames[first].h[i] - dem.lo_z;
    h0[i] = std::isfinite(h) && h > 0 ? h : 0.0;
    fill += h0[i] / nx;
  }
  out.fill_height = fill;
  if (!(fill > d)) throw InputError(cg_fields + ": the bed at t = " + std::to_string(dem.frames[first].t) + " s is less than a grain deep");
  p.reference_height = fill;
  continuum::closure::SectionSettings sec;
  sec.length = out.box_length;
  sec.nx = nx;
  const double period = wall->motion.profile->period();
  sec.max_dt = std::min(period > 0 ? period / 200 : 0.01, (dem.frames[first + 1].t - dem.frames[first].t) / 4);

  // The side walls: the box's width across the section (the cg grid's y extent) and the sliding
  // friction of the first particle batch's material on the box's (side_wall_friction.hpp, (W1)).
  out.side_wall_width = dem.width;
  if (!sc.particles.empty()) {
    const dem::MaterialTable mt = dem::MaterialTable::load(sc.materials_file);
    const int grain = mt.index(sc.particles.front().material, dem_scenario), box = mt.index(wall->material, dem_scenario);
    if (mt.has_pair(grain, box)) out.side_wall_friction = mt.pair(grain, box).friction;
  }
  if (!(out.side_wall_width > 0) || !std::isfinite(out.side_wall_friction)) {
    throw InputError(dem_scenario + ": the side walls' width (cg grid) or the grain-wall pair friction of wall '" + wall->name +
                     "' is unknown");
  }

  // The depth of the surface-speed measure: as given, else the closure's flowing layer.
  const double ell = measure_depth > 0 ? measure_depth : friction.layer_depth;
  out.measure_depth = ell;
  // The DEM measures per frame: slope and surface speed (mass-weighted u_x within ℓ of each column's surface).
  for (std::size_t f = first; f < dem.frames.size(); ++f) {
    const DemFrame& fr = dem.frames[f];
    const double tilt = gravity.tilt(gravity.state(fr.t));
    std::vector<double> hd(nx);
    double speed = 0;
    int cols = 0;
    for (int i = 0; i < nx; ++i) {
      hd[i] = std::isfinite(fr.h[i]) ? fr.h[i] - dem.lo_z : NAN;
      if (!(hd[i] > h_min)) continue;
      double m = 0, pu = 0;
      int top = -1;
      for (std::size_t k = 0; k < dem.z.size(); ++k) {
        const double zk = dem.z[k] - dem.lo_z, rho = fr.density[k * nx + i], u = fr.ux[k * nx + i];
        if (!(rho > 0) || !std::isfinite(u) || zk > hd[i]) continue;
        top = static_cast<int>(k);
        if (hd[i] - zk <= std::min(ell, hd[i])) m += rho, pu += rho * u;
      }
      if (m == 0 && top >= 0) m = 1, pu = fr.ux[top * nx + i];  // the flowing layer thinner than a cell
      if (m > 0) speed += pu / m, ++cols;
    }
    out.times.push_back(fr.t);
    out.tilt_deg.push_back(tilt * 180 / M_PI);
    // Free-surface angle to the horizontal, positive when the +x end is lower (as the tilt).
    out.dem_angle_deg.push_back((tilt - std::atan(slope(xc, hd, h_min))) * 180 / M_PI);
    out.dem_speed.push_back(cols ? speed / cols : NAN);
  }

  // The closure from the DEM's bed, the same two measures from h and u_s (u_s at the centre: mean of
  // the two faces), with the friction given. The surface speed is averaged over the DEM measure's depth
  // min(ℓ, h) (ℓ the a-priori flowing layer) through the closure's own profile u_s e^{−ζ/ℓ_c}.
  struct ClosureSeries {
    std::vector<double> angle_deg, speed;
    std::vector<std::vector<double>> depth;
  };
  auto run_closure = [&](const BedFriction& fr, bool keep_depth) {
    ClosureSeries r;
    sec.friction = fr;
    const double lc = fr.layer_depth;
    continuum::closure::ShallowGranularFlow flow(sec, continuum::closure::ContainerGravity(wall->motion.profile, p), h0,
                                                 dem.frames[first].t);
    for (std::size_t f = first; f < dem.frames.size(); ++f) {
      const double t = dem.frames[f].t;
      if (f > first) flow.advance(t);
      const double tilt = gravity.tilt(gravity.state(t));
      const auto& hc = flow.depth();
      const auto& us = flow.surface_speed();
      double cspeed = 0;
      int ccols = 0;
      for (int i = 0; i < nx; ++i) {
        if (!(hc[i] > h_min)) continue;
        const double u = 0.5 * (us[i] + us[i + 1]), m = std::min(ell, hc[i]);
        cspeed += std::isfinite(lc) ? u * lc * (1 - std::exp(-m / lc)) / m : u;
        ++ccols;
      }
      r.angle_deg.push_back((tilt - std::atan(slope(xc, hc, h_min))) * 180 / M_PI);
      r.speed.push_back(ccols ? cspeed / ccols : NAN);
      if (keep_depth) r.depth.push_back(hc);
    }
    return r;
  };
  BedFriction walled = friction;
  walled.side_walls.width = out.side_wall_width;
  walled.side_walls.friction = out.side_wall_friction;
  {
    ClosureSeries r = run_closure(walled, true);
    out.closure_angle_deg = std::move(r.angle_deg), out.closure_speed = std::move(r.speed), out.closure_depth = std::move(r.depth);
  }
  BedFriction open = friction;
  open.side_walls = continuum::closure::SideWallFriction{};
  {
    ClosureSeries r = run_closure(open, false);
    out.open_angle_deg = std::move(r.angle_deg), out.open_speed = std::move(r.speed);
  }
  rms_max(out.dem_angle_deg, out.open_angle_deg, out.open_angle_rms_error_deg, out.open_angle_max_error_deg);
  rms_max(out.dem_speed, out.open_speed, out.open_speed_rms_error, out.open_speed_max_error);
  {
    // The null model: the first frame's bed held rigid.
    const double s0 = std::atan(slope(xc, h0, h_min));
    std::vector<double> still_angle, still_speed(out.times.size(), 0.0);
    for (double tilt : out.tilt_deg) still_angle.push_back(tilt - s0 * 180 / M_PI);
    const BlockErrors still = block_errors(out.dem_angle_deg, out.dem_speed, still_angle, still_speed, 0, out.times.size());
    out.still_angle_rms_error_deg = still.angle_rms_deg;
    out.still_speed_rms_error = still.speed_rms;
    out.still_agrees = still.agrees;
  }
  rms_max(out.dem_angle_deg, out.closure_angle_deg, out.angle_rms_error_deg, out.angle_max_error_deg);
  rms_max(out.dem_speed, out.closure_speed, out.speed_rms_error, out.speed_max_error);
  if (fit) {
    const ClosureRun closure = [&](const BedFriction& fr, std::vector<double>& a, std::vector<double>& u) {
      ClosureSeries r = run_closure(fr, false);
      a = std::move(r.angle_deg), u = std::move(r.speed);
    };
    out.fit = fit_closure_friction(*fit, cg_fields, out.times, out.dem_angle_deg, out.dem_speed, walled, closure);
  }
  {
    // The bar over all frames: the same definition as the fit's blocks (closure_friction_fit.hpp).
    const BlockErrors all =
        block_errors(out.dem_angle_deg, out.dem_speed, out.closure_angle_deg, out.closure_speed, 0, out.times.size());
    out.dem_speed_rms = all.dem_speed_rms;
    out.agrees = all.agrees;
  }

  fs::create_directories(folder);
  {
    std::ostringstream csv;
    csv << "# flow closure vs coarse-grained DEM (closure_dem_comparison.hpp): " << cg_fields << "\n"
        << "# closure: with side-wall friction mu_w a/W, W = " << out.side_wall_width << " m, mu_w = " << out.side_wall_friction
        << "; closure_2d: without side walls\n"
        << "t_s,tilt_deg,dem_surface_angle_deg,closure_surface_angle_deg,dem_surface_speed_m_s,closure_surface_speed_m_s,"
           "closure_2d_surface_angle_deg,closure_2d_surface_speed_m_s"
        << (out.fit ? ",fitted_surface_angle_deg,fitted_surface_speed_m_s,block" : "") << "\n";
    csv.precision(9);
    for (std::size_t j = 0; j < out.times.size(); ++j) {
      csv << out.times[j] << "," << out.tilt_deg[j] << "," << out.dem_angle_deg[j] << "," << out.closure_angle_deg[j] << ","
          << out.dem_speed[j] << "," << out.closure_speed[j] << "," << out.open_angle_deg[j] << "," << out.open_speed[j];
      if (out.fit) {
        csv << "," << out.fit->angle_deg[j] << "," << out.fit->speed[j] << ","
            << (out.times[j] <= out.fit->settings.train_until ? "train" : "test");
      }
      csv << "\n";
    }
    dem::write_file_atomically((fs::path(folder) / "comparison.csv").string(), csv.str());
  }
  {
    LinePlot lp;
    lp.axes.title = "Free-surface angle: closure vs coarse-grained DEM";
    lp.axes.x_label = "t [s]";
    lp.axes.y_label = "angle to the horizontal [deg]";
    lp.series.push_back({"DEM", out.times, out.dem_angle_deg, LineStyle::solid, Marker::circle});
    lp.series.push_back({"closure, side walls", out.times, out.closure_angle_deg});
    Series open{"closure, no side walls", out.times, out.open_angle_deg};
    open.line = LineStyle::dashed;
    lp.series.push_back(open);
    Series tilt{"box tilt", out.times, out.tilt_deg};
    tilt.line = LineStyle::dashed;
    lp.series.push_back(tilt);
    if (out.fit) add_fit_series(lp, *out.fit, out.times, out.fit->angle_deg, out.tilt_deg);
    draw(lp).write_png((fs::path(folder) / "surface_angle.png").string());
    out.figures.push_back("surface_angle.png");
  }
  {
    LinePlot lp;
    lp.axes.title = "Surface speed along the box: closure vs coarse-grained DEM";
    lp.axes.x_label = "t [s]";
    lp.axes.y_label = "mean surface u_x [m/s]";
    lp.series.push_back({"DEM", out.times, out.dem_speed, LineStyle::solid, Marker::circle});
    lp.series.push_back({"closure, side walls", out.times, out.closure_speed});
    Series open{"closure, no side walls", out.times, out.open_speed};
    open.line = LineStyle::dashed;
    lp.series.push_back(open);
    if (out.fit) add_fit_series(lp, *out.fit, out.times, out.fit->speed, out.dem_speed);
    draw(lp).write_png((fs::path(folder) / "surface_speed.png").string());
    out.figures.push_back("surface_speed.png");
  }
  char buf[640];
  std::snprintf(buf, sizeof buf, "%zu frames from t = %.3g s (the last at rest) to %.3g s; %d columns; the DEM bed is %.3g grain diameters deep.",
                out.times.size(), out.times.front(), out.times.back(), nx, fill / d);
  out.notes.push_back(buf);
  if (period > 0 && out.times.back() - out.times.front() < period) {
    out.notes.push_back("The frames cover less than one motion cycle: the comparison is of part of a cycle.");
  }
  out.notes.push_back("Columns with less than half a grain diameter of grain are left out of both measures (dry floor).");
  std::snprintf(buf, sizeof buf,
                "The DEM box is %.3g m wide across the section (%.2g grain diameters); the closure has the side walls' "
                "friction mu_w a/W with mu_w = %.3g (the DEM's grain-wall sliding friction), %.3g at a flowing layer "
                "of a(h) at the mean depth (Jop, Forterre & Pouliquen 2005); without it (2-D) the errors are "
                "%.2g deg and %.2g m/s RMS.",
                dem.width, dem.width / d, out.side_wall_friction,
                out.side_wall_friction * friction.active_depth(fill) / dem.width, out.open_angle_rms_error_deg,
                out.open_speed_rms_error);
  out.notes.push_back(buf);
  return out;
}

}  // namespace grainscale::studies
