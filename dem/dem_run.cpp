#include "dem/dem_run.hpp"
#include "dem/scaling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include "dem/atomic_file.hpp"
#include "dem/build_description.hpp"
#include "dem/input_error.hpp"
#include "dem/progress.hpp"
#include "dem/snapshot.hpp"
#include "grainscale_version.hpp"

namespace grainscale::dem {

namespace fs = std::filesystem;

namespace {

// The run loop's checks: progress and checkpoint (the clock is read) every kCheckEvery steps, the
// settled test every kSettleEvery steps. The loop steps in goes that end at each (steps_to_next_check).
constexpr std::uint64_t kCheckEvery = 64;
constexpr std::uint64_t kSettleEvery = 100;

std::string seconds(double t) {
  std::ostringstream o;
  o << t;
  return o.str();
}

}  // namespace

DemRun::DemRun(std::string scenario_file, std::string output_override, bool resume)
    : scenario_file_(std::move(scenario_file)), out_dir_(std::move(output_override)), resume_(resume) {}

std::string DemRun::checkpoint_path() const { return (fs::path(out_dir_) / "checkpoint.h5").string(); }

void DemRun::log(const std::string& line) {
  std::cerr << "[dem] " << line << '\n';
  if (log_) log_ << line << '\n' << std::flush;
}

double DemRun::wall_seconds() const {
  return wall_seconds_before_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

void DemRun::setup() {
  scenario_ = load_scenario(scenario_file_);
  if (out_dir_.empty()) out_dir_ = scenario_.output_directory;
  const std::string checkpoint = checkpoint_path();
  // Decide between resuming and starting afresh before anything in the folder changes.
  Checkpoint saved;
  if (resume_) {
    if (!fs::exists(checkpoint)) {
      throw InputError("--resume: there is no checkpoint " + checkpoint +
                       " (the run wrote none before it stopped, or the output folder differs); start without --resume");
    }
    saved = read_checkpoint(checkpoint);
  } else if (fs::exists(checkpoint)) {
    // Never let a fresh start overwrite an unfinished run's only way back.
    CheckpointInfo info;
    try {
      info = read_checkpoint_info(checkpoint);
    } catch (const InputError& e) {
      throw InputError(std::string(e.what()) +
                       "; this unreadable checkpoint is in the output folder: delete it to start afresh");
    }
    if (!info.complete) {
      throw InputError(checkpoint + " holds an unfinished run (stopped at t = " + seconds(info.time) + " s, step " +
                       std::to_string(info.step) +
                       "): continue it with --resume, or delete the checkpoint to start afresh");
    }
  }
  fs::create_directories(fs::path(out_dir_) / "inputs");
  fs::create_directories(fs::path(out_dir_) / "snapshots");
  log_.open(fs::path(out_dir_) / "log.txt", std::ios::app);
  if (!log_) throw std::runtime_error("cannot write " + (fs::path(out_dir_) / "log.txt").string());
  fs::copy_file(scenario_file_, fs::path(out_dir_) / "inputs" / fs::path(scenario_file_).filename(),
                fs::copy_options::overwrite_existing);
  fs::copy_file(scenario_.materials_file, fs::path(out_dir_) / "inputs" / fs::path(scenario_.materials_file).filename(),
                fs::copy_options::overwrite_existing);

  log(version_line() + ", scenario " + scenario_file_);
  // Once, now: every checkpoint records the scenario as the run started (the files may change later).
  fingerprint_ = scenario_fingerprint(scenario_);
  if (resume_) {
    resume_from(std::move(saved));
  } else {
    run_ = build(scenario_);
    for (const std::string& line : run_.report) log(line);
    run_.sim->setup();
    next_snapshot_ = scenario_.snapshot_interval > 0 ? run_.sim->time() : std::numeric_limits<double>::infinity();
  }
  for (const Pour& p : run_.pours) {
    std::ostringstream line;
    line << p.batch().label << ": pours " << p.batch().mass << " kg during the run";
    log(line.str());
  }
  // A scaled run is only as good as its passages are wide in scaled particles (docs/scaling.md).
  for (const std::string& w : narrow_passage_warnings(scenario_)) log("warning: " + w);
  const Simulation& sim = *run_.sim;
  std::ostringstream s;
  s << sim.particles().size() << " spheres in " << sim.bodies().size() << " bodies, " << sim.walls().size()
    << " walls; " << sim.time_step_report() << "; neighbour skin " << sim.neighbors().skin() << " m"
    << (sim.settings().skin > 0 ? " (fixed)" : " (adaptive: chosen at each list build, dem/adaptive_skin.hpp)");
  log(s.str());
}

void DemRun::resume_from(Checkpoint&& c) {
  const std::string& path = c.path;
  if (!c.has_run || !c.has_scenario) {
    throw InputError("--resume: " + path + " was not written by `grainscale dem` (it has no run record)");
  }
  // A checkpoint continues bit for bit only with the code and the scenario that wrote it. Another
  // release may integrate differently: refused. The same release at another revision is allowed
  // (fixes to output or documentation should not strand a long run) but logged.
  const std::string here = checkpoint_code_version();
  const std::string release = c.code_version.substr(0, c.code_version.find(' '));
  if (release != version) {
    throw InputError("--resume: " + path + " was written by grainscale " + c.code_version + ", this is " + here +
                     "; another release may integrate differently, so the run would not continue as it began. "
                     "Resume it with the release that started it, or start afresh.");
  }
  if (c.code_version != here) {
    log("warning: the checkpoint was written by grainscale " + c.code_version + ", this is " + here +
        ": the continuation is bitwise identical to an uninterrupted run only if the two builds integrate alike");
  }
  const std::vector<std::string>& now = fingerprint_;
  const std::vector<std::string>& then = c.run.scenario;
  for (std::size_t k = 0; k < std::max(now.size(), then.size()); ++k) {
    const std::string a = k < then.size() ? then[k] : "(nothing)", b = k < now.size() ? now[k] : "(nothing)";
    if (a != b) {
      throw InputError("--resume: " + scenario_file_ + " differs from the scenario of the run in " + path +
                       " in a way that changes the dynamics:\n  the run had  " + a + "\n  the file has " + b +
                       "\nOn resuming only time.end, time.settle_kinetic_energy and the output keys may change.");
    }
  }
  run_ = build(scenario_, false);
  const double t = c.simulation.time;
  const std::uint64_t step = c.simulation.steps;
  RunRecord record = std::move(c.run);
  restore_checkpoint(std::move(c), run_);
  next_snapshot_ = record.next_snapshot;
  wall_seconds_before_ = record.wall_seconds;
  warned_stability_ = record.warned_stability;
  settled_ = record.settled;
  checkpoint_time_ = t;
  const std::vector<XdmfMesh> meshes = xdmf_meshes(*run_.sim);
  snapshots_.clear();
  for (std::size_t k = 0; k < record.snapshot_time.size(); ++k) {
    snapshots_.push_back({record.snapshot_time[k], record.snapshot_file[k], record.snapshot_particles[k], meshes});
  }
  log("resumed from " + path + " at t = " + seconds(t) + " s, step " + std::to_string(step) + ", after " +
      Progress::format_duration(record.wall_seconds) + " of running; " + std::to_string(snapshots_.size()) +
      " snapshots so far");
}

void DemRun::write_snapshot_now() {
  char name[64];
  std::snprintf(name, sizeof name, "snap_%06zu.h5", snapshots_.size());
  const std::string rel = (fs::path("snapshots") / name).string();
  write_snapshot(*run_.sim, (fs::path(out_dir_) / rel).string(), {scenario_.name, scenario_.seed});
  snapshots_.push_back({run_.sim->time(), rel, run_.sim->particles().size(), xdmf_meshes(*run_.sim)});
  write_xdmf_series((fs::path(out_dir_) / "snapshots.xmf").string(), snapshots_);
}

void DemRun::write_checkpoint_now() {
  RunRecord r;
  r.scenario = fingerprint_;
  r.next_snapshot = next_snapshot_;
  for (const XdmfFrame& f : snapshots_) {
    r.snapshot_time.push_back(f.time);
    r.snapshot_file.push_back(f.h5);
    r.snapshot_particles.push_back(f.particles);
  }
  r.wall_seconds = wall_seconds();
  r.warned_stability = warned_stability_;
  r.settled = settled_;
  r.complete = settled_ || steps_left(*run_.sim) == 0;
  const std::string path = checkpoint_path();
  write_checkpoint(path, run_, &r);
  checkpoint_time_ = run_.sim->time();
  if (on_checkpoint_) on_checkpoint_(path);
}

std::uint64_t DemRun::steps_left(const Simulation& sim) const {
  if (sim.settings().step_control.mode == StepControl::Mode::fixed) {
    const auto total = static_cast<std::uint64_t>(std::ceil(scenario_.end_time / sim.dt() - 1e-9));
    return sim.steps() >= total ? 0 : total - sim.steps();
  }
  const double left = (scenario_.end_time - sim.time()) / sim.dt();
  return left <= 0.5 ? 0 : static_cast<std::uint64_t>(std::llround(left));
}

std::uint64_t DemRun::steps_to_next_check(const Simulation& sim, std::uint64_t steps_left) const {
  // The loop's checks fall on multiples of kCheckEvery (progress, checkpoint), of kSettleEvery, of the
  // stability interval (the warning reads the last check), and at the step whose time reaches the
  // next snapshot's (within half a step): never step past one of them.
  const std::uint64_t s = sim.steps();
  std::uint64_t go = std::min<std::uint64_t>(steps_left, kCheckEvery - s % kCheckEvery);
  if (scenario_.settle_kinetic_energy > 0) go = std::min<std::uint64_t>(go, kSettleEvery - s % kSettleEvery);
  if (const int every = sim.settings().stability_interval; every > 0) {
    go = std::min<std::uint64_t>(go, static_cast<std::uint64_t>(every) - s % static_cast<std::uint64_t>(every));
  }
  // After j more steps the time is time + j dt (to round-off far below the half step): the snapshot
  // is due at the first j >= x.
  const double x = (next_snapshot_ - 0.5 * sim.dt() - sim.time()) / sim.dt();
  if (x < static_cast<double>(go)) go = x <= 1 ? 1 : static_cast<std::uint64_t>(std::floor(x));
  return std::max<std::uint64_t>(go, 1);
}

void DemRun::run() {
  Simulation& sim = *run_.sim;
  started_ = std::chrono::steady_clock::now();
  if (settled_) {
    log("the run had settled when the checkpoint was written: nothing left to step");
    return;
  }
  Progress progress(sim.time(), scenario_.end_time, scenario_.progress_interval, [this](const std::string& l) { log(l); });
  const double interval = scenario_.snapshot_interval;
  auto last_checkpoint = std::chrono::steady_clock::now();
  double lowest_logged = sim.lowest_dt();
  try {
    for (std::uint64_t left = steps_left(sim); left > 0; left = steps_left(sim)) {
      if (sim.time() >= next_snapshot_ - 0.5 * sim.dt()) {
        write_snapshot_now();
        next_snapshot_ += interval;
      }
      // As many steps in one go as leave every check below where it was: each comes at the end of a
      // go (Simulation::run_steps keeps its threads in one parallel region for the steps of a go).
      run_.advance(steps_to_next_check(sim, left));
      if (sim.lowest_dt() < 0.8 * lowest_logged) {  // (the step control: each fall by a fifth, not every change)
        lowest_logged = sim.lowest_dt();
        std::ostringstream m;
        m << "t = " << sim.time() << " s: the step control lowered the time step to " << sim.dt() << " s ("
          << 100 * sim.dt() / sim.dt_ceiling() << " % of the input's " << sim.dt_ceiling() << " s), after a check that found "
          << describe(sim.stability(), sim.bodies());
        log(m.str());
      }
      if (sim.steps() % kCheckEvery == 0) progress.update(sim.time(), sim.steps(), sim.particles().size(), false, sim.dt());
      if (sim.stability().margin > 1 && !warned_stability_) {
        // Warn once: the run goes on (a transient squeeze may pass) but the user should know why it may
        // blow up or why a light particle was shot out.
        warned_stability_ = true;
        log("warning: t = " + std::to_string(sim.time()) + " s: " + describe(sim.stability(), sim.bodies()) +
            ". The time step is too large for this contact network; keep the time step below " +
            std::to_string(sim.dt() / sim.stability().margin) + " s (now " + std::to_string(sim.dt()) + " s).");
      }
      // Settled: every pour done and the kinetic energy below the scenario's threshold.
      if (scenario_.settle_kinetic_energy > 0 && sim.steps() % kSettleEvery == 0 && !run_.pouring()) {
        const Energy e = sim.energy();
        if (e.kinetic_translation + e.kinetic_rotation < scenario_.settle_kinetic_energy) {
          std::ostringstream m;
          m << "settled at t = " << sim.time() << " s: kinetic energy " << e.kinetic_translation + e.kinetic_rotation
            << " J < " << scenario_.settle_kinetic_energy << " J";
          log(m.str());
          settled_ = true;
          break;
        }
      }
      // Checkpoint at the end of a step's work, so that a resumed run enters the loop where this one
      // would have gone on. The clock is read every 64 steps only.
      if (sim.steps() % kCheckEvery == 0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint).count() >=
              scenario_.checkpoint_interval) {
        write_checkpoint_now();
        last_checkpoint = std::chrono::steady_clock::now();
      }
    }
  } catch (const BlowUp& e) {
    // The checkpoint and snapshots on disk are from before the blow-up and stay as they are.
    const std::string kept = checkpoint_time_ >= 0 ? "the last good checkpoint, " + checkpoint_path() + " (t = " +
                                                         seconds(checkpoint_time_) + " s), is kept"
                                                   : "no checkpoint had been written yet";
    const std::string note = std::string(e.what()) + "\nOutput: " + kept + "; " + std::to_string(snapshots_.size()) +
                             " snapshots in " + (fs::path(out_dir_) / "snapshots").string() + " are intact.";
    log("blow-up: " + note);
    throw BlowUp(note);
  } catch (const std::runtime_error& e) {
    // A write failed (disk full, permission): what is already on disk stays, every file being atomic.
    if (dynamic_cast<const InputError*>(&e) != nullptr) throw;
    const std::string note = std::string(e.what()) + ". The run stopped at t = " + seconds(sim.time()) +
                             " s; earlier output in " + out_dir_ + " is intact" +
                             (checkpoint_time_ >= 0 ? " (last checkpoint at t = " + seconds(checkpoint_time_) + " s)" : "");
    log("error: " + note);
    throw std::runtime_error(note);
  }
  for (const std::string& line : run_.pour_report()) log(line);
  progress.update(sim.time(), sim.steps(), sim.particles().size(), true, sim.dt());
  write_checkpoint_now();  // the end: a later --resume with a later time.end goes on from here
}

void DemRun::output() {
  try {
    write_final_output();
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const InputError*>(&e) != nullptr) throw;
    const std::string note = std::string(e.what()) + ". The run itself is complete and its checkpoint " +
                             checkpoint_path() + " saved: fix the cause and rerun with --resume to write the final output";
    log("error: " + note);
    throw std::runtime_error(note);
  }
}

void DemRun::write_final_output() {
  write_snapshot_now();
  const Simulation& sim = *run_.sim;
  const Energy e = sim.energy();
  const double wall = wall_seconds();
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
    << "wall_clock_s: " << wall << "\n"
    << "sphere_steps_per_s: " << (wall > 0 ? sim.steps() * static_cast<double>(sim.particles().size()) / wall : 0) << "\n"
    << "neighbour_list_builds: " << sim.neighbors().builds() << "\n"
    << "neighbour_skin_m: " << sim.neighbors().skin() << "  # of the last build"
    << (sim.settings().skin > 0 ? " (fixed)" : " (adaptive; the largest, the fastest spheres' own)") << "\n"
    << "neighbour_skin_common_m: " << sim.neighbors().smallest_skin() << "  # the skin most spheres had\n"
    << "contacts: " << sim.diagnostics().contacts << "\n"
    << "wall_contacts: " << sim.diagnostics().wall_contacts << "\n"
    << "max_overlap_ratio: " << sim.diagnostics().max_overlap_ratio << "\n"
    << "max_contact_omega_dt: " << sim.diagnostics().max_omega_dt << "  # at the final step, body masses\n"
    << "max_step_stability_margin: " << sim.worst_stability().margin << "  # worst body over the run; > 1 unstable\n";
  if (sim.settings().step_control.mode == StepControl::Mode::stability) {
    y << "time_step_control: stability  # the step kept below a margin of " << sim.settings().step_control.target_margin
      << "\n"
      << "time_step_ceiling_s: " << sim.dt_ceiling() << "\n"
      << "time_step_lowest_s: " << sim.lowest_dt() << "\n"
      << "time_step_changes: " << sim.dt_changes() << "\n"
      << "mean_time_step_s: " << (sim.steps() > 0 ? sim.time() / static_cast<double>(sim.steps()) : 0.0)
      << "  # simulated time / steps, from t = 0\n";
  }
  y
    << "kinetic_energy_J: " << e.kinetic_translation + e.kinetic_rotation << "\n"
    << "snapshots: " << snapshots_.size() << "\n";
  write_file_atomically((fs::path(out_dir_) / "summary.yaml").string(), y.str());
  log("done: " + std::to_string(snapshots_.size()) + " snapshots in " + out_dir_ + "/snapshots, ParaView: " + out_dir_ +
      "/snapshots.xmf");
}

}  // namespace grainscale::dem
