#include "dem/dem_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "dem/atomic_file.hpp"
#include "dem/progress.hpp"
#include "dem/snapshot.hpp"
#include "grainscale_version.hpp"

namespace grainscale::dem {

namespace fs = std::filesystem;

DemRun::DemRun(std::string scenario_file, std::string output_override)
    : scenario_file_(std::move(scenario_file)), out_dir_(std::move(output_override)) {}

void DemRun::log(const std::string& line) {
  std::cerr << "[dem] " << line << '\n';
  if (log_) log_ << line << '\n' << std::flush;
}

void DemRun::setup() {
  scenario_ = load_scenario(scenario_file_);
  if (out_dir_.empty()) out_dir_ = scenario_.output_directory;
  fs::create_directories(fs::path(out_dir_) / "inputs");
  fs::create_directories(fs::path(out_dir_) / "snapshots");
  log_.open(fs::path(out_dir_) / "log.txt", std::ios::app);
  if (!log_) throw std::runtime_error("cannot write " + (fs::path(out_dir_) / "log.txt").string());
  fs::copy_file(scenario_file_, fs::path(out_dir_) / "inputs" / fs::path(scenario_file_).filename(),
                fs::copy_options::overwrite_existing);
  fs::copy_file(scenario_.materials_file, fs::path(out_dir_) / "inputs" / fs::path(scenario_.materials_file).filename(),
                fs::copy_options::overwrite_existing);

  log(std::string("grainscale ") + version + " (" + git_revision + "), scenario " + scenario_file_);
  run_ = build(scenario_);
  for (const std::string& line : run_.report) log(line);
  for (const Pour& p : run_.pours) {
    std::ostringstream line;
    line << p.batch().label << ": pours " << p.batch().mass << " kg during the run";
    log(line.str());
  }
  Simulation& sim = *run_.sim;
  sim.setup();
  std::ostringstream s;
  s << sim.particles().size() << " spheres in " << sim.bodies().size() << " bodies, " << sim.walls().size()
    << " walls; " << sim.time_step_report() << "; neighbour skin " << sim.neighbors().skin() << " m";
  log(s.str());
}

void DemRun::write_snapshot_now() {
  char name[64];
  std::snprintf(name, sizeof name, "snap_%06zu.h5", snapshots_.size());
  const std::string rel = (fs::path("snapshots") / name).string();
  write_snapshot(*run_.sim, (fs::path(out_dir_) / rel).string(), {scenario_.name, scenario_.seed});
  snapshots_.push_back({run_.sim->time(), rel, run_.sim->particles().size(), xdmf_meshes(*run_.sim)});
  write_xdmf_series((fs::path(out_dir_) / "snapshots.xmf").string(), snapshots_);
}

void DemRun::run() {
  Simulation& sim = *run_.sim;
  Progress progress(sim.time(), scenario_.end_time, scenario_.progress_interval, [this](const std::string& l) { log(l); });
  const double interval = scenario_.snapshot_interval;
  double next_snapshot = interval > 0 ? sim.time() : std::numeric_limits<double>::infinity();
  const auto total_steps = static_cast<std::uint64_t>(std::ceil(scenario_.end_time / sim.dt() - 1e-9));
  while (sim.steps() < total_steps) {
    if (sim.time() >= next_snapshot - 0.5 * sim.dt()) {
      write_snapshot_now();
      next_snapshot += interval;
    }
    run_.advance();
    if ((sim.steps() & 63) == 0) progress.update(sim.time(), sim.steps(), sim.particles().size());
    if (sim.stability().margin > 1 && !warned_stability_) {
      // Warn once: the run goes on (a transient squeeze may pass) but the user should know why it may
      // blow up or why a light particle was shot out.
      warned_stability_ = true;
      log("warning: t = " + std::to_string(sim.time()) + " s: " + describe(sim.stability(), sim.bodies()) +
          ". The time step is too large for this contact network; keep the time step below " +
          std::to_string(sim.dt() / sim.stability().margin) + " s (now " + std::to_string(sim.dt()) + " s).");
    }
    // Settled: every pour done and the kinetic energy below the scenario's threshold.
    if (scenario_.settle_kinetic_energy > 0 && (sim.steps() % 100) == 0 && !run_.pouring()) {
      const Energy e = sim.energy();
      if (e.kinetic_translation + e.kinetic_rotation < scenario_.settle_kinetic_energy) {
        std::ostringstream m;
        m << "settled at t = " << sim.time() << " s: kinetic energy " << e.kinetic_translation + e.kinetic_rotation
          << " J < " << scenario_.settle_kinetic_energy << " J";
        log(m.str());
        break;
      }
    }
  }
  for (const std::string& line : run_.pour_report()) log(line);
  progress.update(sim.time(), sim.steps(), sim.particles().size(), true);
  wall_seconds_ = progress.elapsed();
}

void DemRun::output() {
  write_snapshot_now();
  const Simulation& sim = *run_.sim;
  const Energy e = sim.energy();
  std::ostringstream y;
  y << "# grainscale dem run summary\n"
    << "scenario: " << scenario_.name << "\n"
    << "code_version: \"" << version << " " << git_revision << "\"\n"
    << "spheres: " << sim.particles().size() << "\n"
    << "bodies: " << sim.bodies().size() << "\n"
    << "simulated_time_s: " << sim.time() << "\n"
    << "steps: " << sim.steps() << "\n"
    << "time_step_s: " << sim.dt() << "\n"
    << "rayleigh_time_s: " << sim.rayleigh_time() << "\n"
    << "wall_clock_s: " << wall_seconds_ << "\n"
    << "sphere_steps_per_s: " << (wall_seconds_ > 0 ? sim.steps() * static_cast<double>(sim.particles().size()) / wall_seconds_ : 0) << "\n"
    << "neighbour_list_builds: " << sim.neighbors().builds() << "\n"
    << "contacts: " << sim.diagnostics().contacts << "\n"
    << "wall_contacts: " << sim.diagnostics().wall_contacts << "\n"
    << "max_overlap_ratio: " << sim.diagnostics().max_overlap_ratio << "\n"
    << "max_contact_omega_dt: " << sim.diagnostics().max_omega_dt << "  # at the final step, body masses\n"
    << "max_step_stability_margin: " << sim.worst_stability().margin << "  # worst body over the run; > 1 unstable\n"
    << "kinetic_energy_J: " << e.kinetic_translation + e.kinetic_rotation << "\n"
    << "snapshots: " << snapshots_.size() << "\n";
  write_file_atomically((fs::path(out_dir_) / "summary.yaml").string(), y.str());
  log("done: " + std::to_string(snapshots_.size()) + " snapshots in " + out_dir_ + "/snapshots, ParaView: " + out_dir_ +
      "/snapshots.xmf");
}

}  // namespace grainscale::dem
