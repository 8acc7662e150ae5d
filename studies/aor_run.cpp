#include "studies/aor_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "dem/motion/delayed_motion.hpp"
#include "dem/motion/steady_motion.hpp"
#include "dem/progress.hpp"
#include "dem/scaling.hpp"
#include "dem/scenario.hpp"
#include "dem/snapshot.hpp"

namespace grainscale::studies {

namespace {

struct Motion {
  double rms = 0, p95 = 0, max = 0;  // m/s
  std::size_t count = 0;
};

/// Speeds of the bodies whose centre is over the tray (horizontal radius <= tray_r) and above
/// `z_min`: the pile, not what overflowed onto the floor. "At rest" is judged by the 95th percentile,
/// so that a few rattlers on the surface do not hold up a run, as one grain at 1 m/s among 2000 would
/// through the rms.
Motion tray_motion(const dem::Simulation& sim, double tray_r, double z_min) {
  const dem::Bodies& b = sim.bodies();
  std::vector<double> speed;
  double sum = 0;
  Motion m;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const dem::Vec3& x = b.x[i];
    if (x.z < z_min || x.x * x.x + x.y * x.y > tray_r * tray_r) continue;
    speed.push_back(norm(b.v[i]));
    sum += norm2(b.v[i]);
  }
  m.count = speed.size();
  if (m.count == 0) return m;
  m.rms = std::sqrt(sum / m.count);
  const auto k = speed.begin() + static_cast<std::ptrdiff_t>(0.95 * (m.count - 1));
  std::nth_element(speed.begin(), k, speed.end());
  m.p95 = *k;
  m.max = *std::max_element(speed.begin(), speed.end());
  return m;
}

}  // namespace

AorRunResult run_aor(const std::string& scenario_file, const AorCase& c, const std::string& snapshot_file,
                     const std::function<void(const std::string&)>& log) {
  AorRunResult out;
  auto warn = [&](const std::string& w) {
    out.warnings.push_back(w);
    log("warning: " + w);
  };
  const dem::Scenario sc = dem::load_scenario(scenario_file);
  for (const std::string& w : dem::narrow_passage_warnings(sc)) warn(w);
  dem::BuiltScenario built = dem::build(sc);
  dem::Simulation& sim = *built.sim;
  sim.setup();
  out.time_step = sim.dt();
  log(sim.time_step_report());

  const AorSchedule earliest = aor_schedule(c);
  const double tray_r = 0.5 * c.rig.tray_diameter, pipe_r = 0.5 * c.rig.pipe_diameter;
  const double z_floor = -0.5 * c.rig.floor_depth;  // below: grain that overflowed onto the floor
  const double size = dem::largest_particle_size(sc);
  int pipe = -1;
  for (std::size_t w = 0; w < sim.walls().size(); ++w) {
    if (sim.walls()[w].name() == "pipe") pipe = static_cast<int>(w);
  }
  if (pipe < 0) throw std::invalid_argument(scenario_file + ": the AOR scenario has no wall named 'pipe'");
  // The pipe must not move until the fill is at rest: hold it, and give it its motion when the lift
  // begins (below), at the time that is then written back into the scenario.
  sim.walls()[pipe].set_motion({});
  const auto t0 = std::chrono::steady_clock::now();
  dem::Progress progress(0, earliest.end_time, 30, log);
  const auto every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(0.02 / sim.dt())));
  // Waiting for the fill to settle is bounded: by then something is wrong (say so and lift anyway).
  const double latest_lift = earliest.lift_start + std::max(2.0, 5 * c.timing.settle_fill);
  bool lifted = false;
  double end_time = std::numeric_limits<double>::infinity();  // set at the lift
  double next_report = earliest.lift_start;
  out.clear_time = end_time;
  while (sim.time() < end_time) {
    built.advance();
    if ((sim.steps() & 255) == 0) progress.update(sim.time(), sim.steps(), sim.particles().size(), false, sim.dt());
    out.max_stability_margin = std::max(out.max_stability_margin, sim.stability().margin);
    if (!lifted && sim.time() >= earliest.lift_start && sim.steps() % every == 0) {
      // Lift once the pour is done and the fill has come to rest.
      const Motion fill = tray_motion(sim, pipe_r, z_floor);
      const bool late = sim.time() >= latest_lift;
      if ((built.pouring() || fill.p95 >= c.timing.fill_rest_speed) && !late) {
        if (sim.time() >= next_report) {
          next_report += 0.25;
          std::ostringstream m;
          m << "t = " << sim.time() << " s: waiting for the fill: pour " << (built.pouring() ? "under way" : "done")
            << ", speeds: 95th percentile " << fill.p95 << " m/s, rms " << fill.rms << ", max " << fill.max;
          log(m.str());
        }
        continue;
      }
      lifted = true;
      out.pour_done = !built.pouring();
      out.fill_speed_p95 = fill.p95;
      if (late) {
        std::ostringstream m;
        m << "the fill had not come to rest by t = " << sim.time() << " s (pour " << (out.pour_done ? "done" : "not done")
          << ", 95th-percentile speed " << fill.p95 << " m/s); lifting anyway";
        warn(m.str());
      }
      // The lift starts at the next step; its time, written with all its digits, goes into the
      // scenario so that `grainscale dem` on that file repeats this run.
      out.lift_start = sim.time();
      const AorSchedule actual = aor_schedule(c, out.lift_start);
      auto steady = std::make_shared<dem::SteadyMotion>(dem::Vec3{0, 0, c.rig.lift_speed}, dem::Vec3{});
      sim.walls()[pipe].set_motion({std::make_shared<dem::DelayedMotion>(steady, out.lift_start), {}});
      {
        std::ofstream f(scenario_file);
        f << aor_scenario_yaml(c, sc.output_directory, out.lift_start);
      }
      const dem::Particles& p = sim.particles();
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.x[i].x * p.x[i].x + p.x[i].y * p.x[i].y <= pipe_r * pipe_r) out.fill_top = std::max(out.fill_top, p.x[i].z + p.radius[i]);
      }
      out.clear_time = out.lift_start + (out.fill_top + size) / c.rig.lift_speed;
      end_time = std::min(actual.end_time, out.clear_time + c.timing.max_settle);
      std::ostringstream m;
      m << "lift at t = " << sim.time() << " s: " << sim.bodies().size() << " particles, fill top " << out.fill_top * 1e3
        << " mm, speeds: 95th percentile " << fill.p95 << " m/s, rms " << fill.rms << " m/s; the pipe clears the grain at t = "
        << out.clear_time << " s";
      log(m.str());
      if (out.fill_top > c.rig.pipe_length) {
        warn("the fill stands " + std::to_string(out.fill_top * 1e3) + " mm high, above the pipe's length of " +
             std::to_string(c.rig.pipe_length * 1e3) + " mm: pour less grain");
      }
    }
    if (lifted && sim.time() >= out.clear_time && sim.steps() % every == 0) {
      const Motion m = tray_motion(sim, tray_r, z_floor);
      out.speed_p95 = m.p95;
      if (m.p95 < c.timing.rest_speed) {
        out.at_rest = true;
        break;
      }
    }
  }
  progress.update(sim.time(), sim.steps(), sim.particles().size(), true, sim.dt());
  out.end_time = sim.time();
  out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.spheres = sim.particles().size();
  out.bodies = sim.bodies().size();
  out.bodies_on_tray = tray_motion(sim, tray_r, -0.5 * c.rig.floor_depth).count;
  out.max_overlap_ratio = sim.diagnostics().max_overlap_ratio;
  if (!out.at_rest) {
    std::ostringstream m;
    m << "the pile was still moving at t = " << sim.time() << " s (95th-percentile speed " << out.speed_p95 << " m/s > "
      << c.timing.rest_speed << " m/s); its angle may still change";
    warn(m.str());
  }
  if (!snapshot_file.empty()) dem::write_snapshot(sim, snapshot_file, {sc.name, sc.seed});

  const dem::Particles& p = sim.particles();
  AngleSettings st;
  st.outer_radius = tray_r;
  out.angle = measure_angle(p.x, p.radius, st);
  std::ostringstream m;
  m.precision(4);
  m << "angle of repose " << out.angle.mean_deg << " +- " << out.angle.spread_deg << " deg (surface, "
    << out.angle.sector_deg.size() << " sectors), " << out.angle.side_mean_deg << " +- " << out.angle.side_spread_deg
    << " deg (side projection); " << out.bodies_on_tray << " of " << out.bodies << " particles on the tray; "
    << out.wall_seconds << " s wall clock";
  log(m.str());
  return out;
}

}  // namespace grainscale::studies
