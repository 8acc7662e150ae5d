// The `grainscale` command. Each subcommand runs one stage; `--help` works everywhere.
#include <malloc.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "coarsegrain/cg_run.hpp"
#include "continuum/run_continuum.hpp"
#include "dem/build_description.hpp"
#include "dem/checkpoint.hpp"
#include "dem/dem_run.hpp"
#include "dem/force_field.hpp"
#include "dem/input_error.hpp"
#include "dem/scenario.hpp"
#include "dem/shape.hpp"
#include "studies/calibrate_command.hpp"
#include "studies/cg_plots.hpp"
#include "studies/fit_command.hpp"
#include "studies/loop_command.hpp"
#include "studies/hold_command.hpp"
#include "studies/openmp_wait_policy.hpp"
#include "studies/option_number.hpp"
#include "studies/shape_picture.hpp"
#include "studies/study_kinds.hpp"

namespace {

using namespace grainscale;

const char* kUsage = R"(grainscale - chaff and grain movement in shaken bulk grain

usage: grainscale <command> [options]

commands:
  study STUDY.yaml [--out DIR] [--threads N] [--resume]
        run a study end to end: DEM -> coarse-graining -> fit -> prediction ->
        report.md with figures and the comparison with the report's measurements;
        the folder holds inputs/, stages/ (each stage's settings, runnable alone),
        dem/, cg/, fit/, predict/, log.txt (docs/studies.md). --resume continues
        the DEM stage from its checkpoint
  dem SCENARIO.yaml [--out DIR] [--threads N] [--resume]
        run a DEM scenario: insert particles, step to the end time, write HDF5
        snapshots (+ XDMF for ParaView), summary.yaml and log.txt in the output folder;
        checkpoint.h5 there is updated every output.checkpoint_interval s of wall clock
        and at the end, and --resume continues a stopped run from it, bit for bit
  bench SCENARIO.yaml [--steps N] [--threads LIST] [--settled CHECKPOINT.h5] [--from CHECKPOINT.h5] [--warmup W]
        [--large-bed-from S]
        settle the scenario to its end time, then time N further steps (default
        20000) from the same settled state on each thread count in LIST (default
        1,2), after W untimed ones (default 200); prints sphere-steps per second and
        the speed-up. --settled FILE keeps the settled state as a checkpoint: read if
        it exists, written otherwise. --from FILE settles on from that state (a
        checkpoint of the same bed at an earlier time) instead of from the insertion.
        --large-bed-from S: the force loop takes its path for beds beyond the caches
        (prefetches, entries in chunks, the completion front) from S spheres on
        (default 50000; 0: every bed), to measure what that path costs or gains
        (docs/performance.md); the same numbers either way
  cg SETTINGS.yaml [--out DIR] [--threads N]
        coarse-grain DEM snapshots into fields in the container frame (HDF5 + XDMF,
        CSV) and the report's measures: chaff per 50 mm slice, top-view coverage,
        congregation index, with PNG figures of each (settings: docs/coarsegrain_layout.md)
  predict SETTINGS.yaml [--out DIR]
        run the continuum advection-diffusion-segregation model (SUNDIALS CVODE or
        SSP-RK3) and write c(x, z, t), chaff per slice and surface coverage
        (settings: docs/continuum.md)
  hold SETTINGS.yaml [--out DIR]
        hold-scale prediction without DEM: a depth-averaged granular flow closure
        on the moving container drives the chaff model over days of motion
        (resolved cycles, then the cycle-averaged model); writes surface chaff,
        end-wall shares, spear samples, maps (PNG, CSV, HDF5) (docs/hold_prediction.md)
  fit SETTINGS.yaml [--out DIR]
        fit continuum coefficients (S, C, D0, kappa, ...) to concentration fields
        and/or coverage profiles (CSV); writes fit.yaml (values, standard errors,
        correlations, chi2/dof), report.md and PNGs of data, model and residual;
        exit status 4 if it did not converge or left a parameter unconstrained
        (settings: docs/plots.md)
  loop SETTINGS.yaml [--out DIR]
        close the loop with measured data: fit the model (a `fit` settings file),
        diagnose the residual (symmetry, surface/bulk, harmonics, walls, c, whiteness),
        rank candidate effects by blocked cross-validation and BIC, add the winner
        if justified; loop.yaml, report.md (error before/after) and PNGs (docs/loop.md)
  calibrate STUDY.yaml [--out DIR] [--threads N] [--case NAME[,NAME...]]
        calibrate sliding and/or rolling friction against measured angles of
        repose with the report's rig (pipe lifted off a tray); writes runs.csv,
        calibrated materials, sensitivity PNGs and report.md (docs/aor_calibration.md);
        --case (repeatable) runs only the named cases, e.g. one per process and --out
  shape SHAPE.yaml [--png FILE.png] [--density KG_M3 | --mass KG]
        check a particle shape: size against the measured size, volume, centroid,
        principal moments; with --mass, the density that gives that particle mass
        (e.g. the thousand-grain mass / 1000); --png draws top, side and end views
  version
        print the version, its git revision and the build (compiler, instruction set)

Scenario format: docs/scenario.md. Snapshot layout: docs/snapshot_layout.md.
)";

/// `grainscale CMD --help`: the usage entry of CMD (its line and the indented lines under it), or
/// everything for an unknown command.
std::string command_usage(const std::string& cmd) {
  std::istringstream in(kUsage);
  std::string line, entry;
  bool inside = false;
  for (std::getline(in, line); in; std::getline(in, line)) {
    const bool starts_entry = line.rfind("  ", 0) == 0 && line.size() > 2 && line[2] != ' ';
    if (starts_entry) inside = line.substr(2, cmd.size() + 1) == cmd + " " || line.substr(2) == cmd;
    else if (!line.empty() && line[0] != ' ') inside = false;
    if (inside) entry += line + "\n";
  }
  if (entry.empty()) return kUsage;
  return "usage: grainscale " + entry.substr(2) + "\n(all commands: grainscale --help)\n";
}

struct Args {
  std::vector<std::string> positional;
  std::string out;
  std::string threads;
  std::string png;
  double density = 0, mass = 0;
  long steps = 20000;
  long warmup = 200;  // bench: untimed steps before the timed ones
  long large_bed_from = -1;  // bench: dem::beyond_cache_spheres() for the timed steps (-1: as it is)
  bool resume = false;
  std::string settled;  // bench: checkpoint of the settled state (read if present, else written)
  std::string from;     // bench: a state to settle from instead of the scenario's insertion
  std::vector<std::string> cases;  // calibrate: every --case value
};

Args parse(int argc, char** argv, int first) {
  Args a;
  for (int i = first; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const char* name) {
      if (i + 1 >= argc) throw InputError(std::string("option ") + name + " needs a value");
      return std::string(argv[++i]);
    };
    auto positive = [&](const char* name) {
      const double d = studies::number_option(name, value(name));
      if (!(d > 0) || !std::isfinite(d)) throw InputError(std::string(name) + " must be positive");
      return d;
    };
    if (s == "--out") a.out = value("--out");
    else if (s == "--png") a.png = value("--png");
    else if (s == "--density") a.density = positive("--density");
    else if (s == "--mass") a.mass = positive("--mass");
    else if (s == "--threads") a.threads = value("--threads");
    else if (s == "--resume") a.resume = true;
    else if (s == "--settled") a.settled = value("--settled");
    else if (s == "--from") a.from = value("--from");
    else if (s == "--case") a.cases.push_back(value("--case"));
    else if (s == "--steps") {
      a.steps = studies::whole_number_option("--steps", value("--steps"));
      if (a.steps < 1) throw InputError("--steps must be at least 1");
    } else if (s == "--warmup") {
      a.warmup = studies::whole_number_option("--warmup", value("--warmup"));
      if (a.warmup < 0) throw InputError("--warmup must be 0 or more");
    } else if (s == "--large-bed-from") {
      a.large_bed_from = studies::whole_number_option("--large-bed-from", value("--large-bed-from"));
      if (a.large_bed_from < 0) throw InputError("--large-bed-from must be 0 or more (spheres)");
    } else if (s.rfind("--", 0) == 0) throw InputError("unknown option " + s + " (see grainscale --help)");
    else a.positional.push_back(s);
  }
  return a;
}

std::vector<int> thread_list(const std::string& s, std::vector<int> fallback) {
  if (s.empty()) return fallback;
  std::vector<int> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(studies::thread_count_option(item));
  return out;
}

int run_dem(const Args& a) {
  if (a.positional.size() != 1) {
    throw InputError("usage: grainscale dem SCENARIO.yaml [--out DIR] [--threads N] [--resume]");
  }
  for (int t : thread_list(a.threads, {})) omp_set_num_threads(t);
  dem::DemRun run(a.positional[0], a.out, a.resume);
  run.setup();
  run.run();
  run.output();
  return 0;
}

/// FNV-1a over the bytes of the bodies' positions, orientations, velocities and angular momenta,
/// in id order (the array order follows the spheres' and is not part of the state).
std::uint64_t state_fingerprint(const dem::Bodies& b) {
  std::uint64_t h = 1469598103934665603ull;
  const std::vector<std::size_t> at = b.indices_by_id();
  auto add = [&](const auto& v) {
    for (std::size_t k = 0; k < v.size(); ++k) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(&v[at[k]]);
      for (std::size_t c = 0; c < sizeof(v[0]); ++c) h = (h ^ bytes[c]) * 1099511628211ull;
    }
  };
  add(b.x), add(b.q), add(b.v), add(b.L);
  return h;
}

/// This process's resident memory now (Linux: VmRSS of /proc/self/status), bytes; 0 if unknown.
std::size_t resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return 0;
  char line[256];
  std::size_t kb = 0;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::sscanf(line, "VmRSS: %zu kB", &kb) == 1) break;
  }
  std::fclose(f);
  return kb * 1024;
}

/// The timed steps of `bench`, in a function of their own so that a profiler can count them alone
/// (bench/run_cache_profile.sh: callgrind --toggle-collect=*timed_steps*).
[[gnu::noinline]] void timed_steps(dem::Simulation& sim, long steps) {
  sim.run_steps(static_cast<std::uint64_t>(steps));
}

int run_bench(const Args& a) {
  // Large arrays in their own mappings, returned to the system when freed (fixed thresholds: glibc's
  // adaptive ones would serve a later array from memory a freed one left resident), so that the
  // resident growth below is what the copied simulation holds. The timed steps allocate nothing.
  mallopt(M_MMAP_THRESHOLD, 1 << 16);
  mallopt(M_TRIM_THRESHOLD, 1 << 16);
  if (a.positional.size() != 1) {
    throw InputError("usage: grainscale bench SCENARIO.yaml [--steps N] [--threads LIST] [--settled CHECKPOINT.h5] "
                     "[--from CHECKPOINT.h5] [--warmup W] [--large-bed-from S]");
  }
  if (!a.from.empty() && !std::filesystem::is_regular_file(a.from)) {
    throw InputError("--from: " + a.from + " is not a file (a checkpoint written by `grainscale bench --settled` or `grainscale dem`)");
  }
  const dem::Scenario sc = dem::load_scenario(a.positional[0]);
  dem::BuiltScenario built = dem::build(sc);
  dem::Simulation* sim = built.sim.get();
  sim->setup();
  std::cerr << "[bench] " << sim->particles().size() << " spheres; " << sim->time_step_report() << "\n";
  // A large bed takes long to settle: keep the settled state as a checkpoint and start from it next time.
  const bool from_checkpoint = !a.settled.empty() && std::filesystem::exists(a.settled);
  if (from_checkpoint) {
    dem::restore_checkpoint(dem::read_checkpoint(a.settled), built);
    std::cerr << "[bench] settled state from " << a.settled << " (t = " << sim->time() << " s)"
              << (a.from.empty() ? "" : "; --from " + a.from + " not used") << "\n";
  } else {
    // --from: settle on from a state reached before (a poured bed, say, into the tilting that follows).
    if (!a.from.empty()) {
      dem::restore_checkpoint(dem::read_checkpoint(a.from), built);
      std::cerr << "[bench] starting from " << a.from << " (t = " << sim->time() << " s)\n";
    }
    std::cerr << "[bench] settling to t = " << sc.end_time << " s ...\n";
  }
  double next_report = 0;
  while (!from_checkpoint && sim->time() < sc.end_time) {
    built.advance();
    if (sim->time() >= next_report) {  // progress: settling a large bed takes a while
      std::cerr << "[bench] t = " << sim->time() << " s, " << sim->particles().size() << " spheres, "
                << sim->diagnostics().contacts << " contacts\n";
      next_report += 0.05;
    }
  }
  if (!from_checkpoint && !a.settled.empty()) {
    dem::write_checkpoint(a.settled, built);
    std::cerr << "[bench] settled state written to " << a.settled << "\n";
  }
  std::printf("problem: %s, %zu spheres, dt = %.4g s, settled for %.3g s, %zu contacts, %zu wall contacts\n",
              sc.name.c_str(), sim->particles().size(), sim->dt(), sim->time(), sim->diagnostics().contacts,
              sim->diagnostics().wall_contacts);
  std::printf("memory: %.0f bytes per sphere\n", static_cast<double>(sim->bytes()) / sim->particles().size());
  {
    // How waiting threads behave decides the 2-thread figure (studies/openmp_wait_policy.hpp).
    std::string waiting;
    if (const char* policy = std::getenv("OMP_WAIT_POLICY")) waiting = std::string("OMP_WAIT_POLICY=") + policy;
    if (const char* spin = std::getenv("GOMP_SPINCOUNT")) waiting += (waiting.empty() ? "" : ", ") + std::string("GOMP_SPINCOUNT=") + spin;
    std::printf("OpenMP waiting: %s\n", waiting.empty() ? "libgomp default" : waiting.c_str());
  }
  // The force loop's path for beds beyond the caches (dem/force_field.hpp), set for the timed steps
  // only: the settling above is the same either way, bit for bit.
  if (a.large_bed_from >= 0) dem::beyond_cache_spheres() = static_cast<std::size_t>(a.large_bed_from);
  std::printf("force loop: %s (from %zu spheres on)\n",
              sim->particles().size() >= dem::beyond_cache_spheres() ? "the large-bed path" : "the in-cache path",
              dem::beyond_cache_spheres());
  double base = 0;  // the first thread count's rate, once timed
  for (int threads : thread_list(a.threads, {1, 2})) {
    omp_set_num_threads(threads);
    const bool first = base == 0;
    // What one simulation holds in memory: the resident growth from copying it and running it (the
    // process's peak also holds the scenario's own bed, inserted before the settled state replaced it,
    // and this copy beside the original).
    const std::size_t resident_before = first ? resident_bytes() : 0;
    dem::Simulation copy = *sim;
    copy.run_steps(static_cast<std::uint64_t>(a.warmup));  // warm caches and buffers
    const std::size_t builds0 = copy.neighbors().builds();
    const double sim0 = copy.time();
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    timed_steps(copy, a.steps);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;  // all threads
    const double rate = static_cast<double>(a.steps) * copy.particles().size() / s;
    if (base == 0) base = rate;
    std::printf("threads %d: %ld steps in %.3f s = %.3f M sphere-steps/s (%.2fx of first), %.3g contacts/s, "
                "%zu neighbour-list builds\n", threads, a.steps, s, rate / 1e6, rate / base,
                static_cast<double>(copy.diagnostics().contacts) * a.steps / s, copy.neighbors().builds() - builds0);
    // (With the step control the step varies: what the timed steps covered, for simulated time per hour.)
    std::printf("threads %d: simulated %.6g s in the timed steps (mean step %.4g s) = %.3f simulated s per wall-clock hour\n",
                threads, copy.time() - sim0, (copy.time() - sim0) / static_cast<double>(a.steps), (copy.time() - sim0) / s * 3600);
    if (first && resident_before > 0) {
      const std::size_t after = resident_bytes();
      std::printf("resident: %.0f bytes per sphere (one simulation: the memory its copy made resident over %ld steps)\n",
                  after > resident_before ? static_cast<double>(after - resident_before) / copy.particles().size() : 0.0,
                  a.steps + a.warmup);
    }
    // Every thread count (and every build of the code that claims to leave results unchanged) must
    // end in the same state, bit for bit: a fingerprint of the bodies' state says whether it did.
    const dem::Energy e = copy.energy();
    // CPU time: on a shared machine the fairer figure of the work done (other jobs stretch the wall clock).
    std::printf("threads %d: CPU %.3f s = %.3f M sphere-steps per CPU second; end state: kinetic energy %.6e J, "
                "%zu contacts, fingerprint %016llx\n", threads, cpu, static_cast<double>(a.steps) * copy.particles().size() / cpu / 1e6,
                e.kinetic_translation + e.kinetic_rotation, copy.diagnostics().contacts,
                static_cast<unsigned long long>(state_fingerprint(copy.bodies())));
    // The skin is chosen at each build (dem/adaptive_skin.hpp): what the timed steps ended with.
    // (The skin is the largest, the fastest spheres' own; the common one is what most spheres had.)
    std::printf("threads %d: neighbour list at the end: skin %.4g m, %.2f entries per sphere, common skin %.4g m\n",
                threads, copy.skin(), static_cast<double>(copy.neighbors().entries()) / copy.particles().size(),
                copy.neighbors().smallest_skin());
  }
  return 0;
}

int run_cg(const Args& a) {
  if (a.positional.size() != 1) throw InputError("usage: grainscale cg SETTINGS.yaml [--out DIR] [--threads N]");
  for (int t : thread_list(a.threads, {})) omp_set_num_threads(t);
  cg::CgSettings settings = cg::load_cg_settings(a.positional[0]);
  if (!a.out.empty()) settings.output_dir = a.out;
  const cg::CgSummary s = cg::run_coarse_graining(settings);
  std::printf("coarse-grained %d snapshots into %d frames (kernel width %.4g m, true diameter %.4g m); "
              "worst mass error %.2g\n",
              s.snapshots, s.frames, s.kernel_width, s.true_diameter, s.max_mass_error);
  for (const std::string& w : s.warnings) std::printf("warning: %s\n", w.c_str());
  if (!s.congregation.empty()) {
    const cg::CongregationIndex& c = s.congregation.back();
    std::printf("last snapshot: chaff at the ends / overall %.3g (left) %.3g (right); top-view coverage left %.3g, "
                "centre %.3g, right %.3g\n",
                c.left, c.right, c.coverage_left, c.coverage_centre, c.coverage_right);
  }
  studies::write_cg_plots(s.output_dir, std::cout);  // PNG figures beside the CSV files
  std::printf("output: %s\n", s.output_dir.c_str());
  return 0;
}

int run_predict(const Args& a) {
  if (a.positional.size() != 1) throw InputError("usage: grainscale predict SETTINGS.yaml [--out DIR]");
  continuum::ContinuumSettings settings = continuum::load_continuum_settings(a.positional[0]);
  if (!a.out.empty()) settings.output_folder = a.out;
  const auto t0 = std::chrono::steady_clock::now();
  const continuum::ContinuumRunSummary s = continuum::run_continuum(settings);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("continuum run in %.3g s; chaff %.6g -> %.6g m^2 per unit width (relative change %.2g); "
              "c in [%.4g, %.4g]\n",
              wall, s.chaff_initial, s.chaff_final,
              s.chaff_initial > 0 ? (s.chaff_final - s.chaff_initial) / s.chaff_initial : 0.0, s.c_min, s.c_max);
  std::printf("output: %s, %s, %s\n", s.h5_file.c_str(), s.slices_file.c_str(), s.coverage_file.c_str());
  return 0;
}

int run_shape(const Args& a) {
  if (a.positional.size() != 1) throw InputError("usage: grainscale shape SHAPE.yaml [--png FILE.png] [--density KG_M3 | --mass KG]");
  if (a.density > 0 && a.mass > 0) throw InputError("give --density or --mass, not both");
  const dem::Shape s = dem::load_shape(a.positional[0]);
  const dem::MassProperties mp = dem::union_mass_properties(s.spheres);
  const dem::Vec3 b = s.bounding_size();
  std::printf("shape %s: %zu spheres\n", s.name.c_str(), s.spheres.size());
  if (!s.source.empty()) std::printf("source: %s\n", s.source.c_str());
  std::printf("bounding box: %.4g x %.4g x %.4g mm\n", b.x * 1e3, b.y * 1e3, b.z * 1e3);
  const auto dims = s.sorted_dimensions();
  for (std::size_t k = 0; k < s.measured_size.size(); ++k) {
    std::printf("  %s %.4g mm, measured %.4g mm (%+.2f %%)\n", k == 0 ? "length" : k == 1 ? "width" : "thickness",
                dims[k] * 1e3, s.measured_size[k] * 1e3, 100 * (dims[k] / s.measured_size[k] - 1));
  }
  std::printf("volume (overlaps counted once): %.5g mm^3; equivalent sphere diameter %.4g mm\n", mp.volume * 1e9,
              2e3 * std::cbrt(3 * mp.volume / (4 * M_PI)));
  std::printf("centroid: (%.4g, %.4g, %.4g) mm\n", mp.centroid.x * 1e3, mp.centroid.y * 1e3, mp.centroid.z * 1e3);
  std::printf("principal moments per density: %.5g, %.5g, %.5g mm^5\n", mp.principal_moments.x * 1e15,
              mp.principal_moments.y * 1e15, mp.principal_moments.z * 1e15);
  if (a.density > 0) std::printf("mass at %.6g kg/m^3: %.5g mg\n", a.density, a.density * mp.volume * 1e6);
  if (a.mass > 0) {
    std::printf("density for a particle mass of %.5g mg: %.5g kg/m^3\n", a.mass * 1e6, a.mass / mp.volume);
  }
  if (!a.png.empty()) {
    studies::draw_shape(s).write_png(a.png);
    std::printf("picture (top, side, end views; bar = 1 mm): %s\n", a.png.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  studies::choose_openmp_spin(argv);  // before any OpenMP: see openmp_wait_policy.hpp
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "help")) {
    std::cout << kUsage;
    return argc < 2 ? 1 : 0;
  }
  const std::string cmd = argv[1];
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::cout << command_usage(cmd);
      return 0;
    }
  }
  try {
    const Args a = parse(argc, argv, 2);
    if (cmd == "study") return studies::study_command(a.positional, a.out, a.threads, a.resume);
    if (cmd == "dem") return run_dem(a);
    if (cmd == "bench") return run_bench(a);
    if (cmd == "cg") return run_cg(a);
    if (cmd == "predict") return run_predict(a);
    if (cmd == "hold") return studies::hold_command(a.positional, a.out);
    if (cmd == "fit") return studies::fit_command(a.positional, a.out);
    if (cmd == "loop") return studies::loop_command(a.positional, a.out);
    if (cmd == "calibrate") return studies::calibrate_main(a.positional, a.out, a.threads, a.cases);
    if (cmd == "shape") return run_shape(a);
    if (cmd == "version") {
      std::cout << dem::version_line() << "\n";
      return 0;
    }
    std::cerr << "grainscale: unknown command '" << cmd << "' (see grainscale --help)\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "grainscale: input error: " << e.what() << "\n";
    return 2;
  } catch (const dem::BlowUp& e) {
    std::cerr << "grainscale: the simulation blew up and was stopped: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "grainscale: error: " << e.what() << "\n";
    return 1;
  }
}
