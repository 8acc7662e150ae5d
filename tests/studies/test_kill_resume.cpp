// Issue 12, "Long runs": the real `grainscale dem` binary, killed with SIGKILL part-way and continued
// with --resume (twice, on another thread count), ends with the same snapshots, XDMF series and run
// summary (wall-clock fields aside), byte for byte, as a run never interrupted.
//
// No timing races: the test waits (polling the output folder, bounded) until a checkpoint exists
// before it kills, so a kill always leaves something to resume from. Where exactly the kill lands
// after that (mid-step, mid-snapshot, mid-checkpoint write) varies from run to run, and every place
// must give the same result: that is the guarantee. The scenario runs thousands of steps after the
// first checkpoint appears (a second or more of CPU), far longer than the poll interval, so a kill
// never comes after the run has finished; if it did, the test says so instead of passing.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "dem/checkpoint.hpp"

namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "grainscale_kill_XXXXXX").string();
    REQUIRE(mkdtemp(tmpl.data()) != nullptr);
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

std::string slurp(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A pour still running, clumps and loose spheres with EPSD rolling histories, a surging mesh box:
// everything a checkpoint must carry. 0.15 s simulated, about 3800 steps; a checkpoint every 20 ms of
// wall clock (checked every 64 steps), a snapshot every 0.01 s.
void write_scenario(const TempDir& dir) {
  std::ofstream(dir / "materials.yaml") << R"(materials:
  grain: {density: 1000, shear_modulus: 5.0e5, poisson_ratio: 0.3}
  wall:  {density: 1190, shear_modulus: 7.97e8, poisson_ratio: 0.38}
pairs:
  grain-grain: {restitution: 0.2, friction: 0.5, rolling_friction: 0.1}
  grain-wall:  {restitution: 0.2, friction: 0.4, rolling_friction: 0.05}
)";
  std::ofstream(dir / "rod.yaml") << "name: rod\nlength_unit: mm\nspheres:\n  - {center: [-1.5, 0, 0], radius: 1.3}\n"
                                     "  - {center: [0, 0, 0], radius: 1.6}\n  - {center: [1.5, 0, 0], radius: 1.3}\n";
  std::ofstream(dir / "scenario.yaml") << R"(name: kill_resume
seed: 11
gravity: [0, 0, -150]
materials: materials.yaml
contact: {rolling: epsd}
time: {end: 0.15, pour_interval: 0.002}
walls:
  - {name: box, type: box_mesh, min: [0, 0, 0], max: [0.04, 0.03, 0.06], open: [+z], material: wall,
     motion: {type: sinusoids, surge: {amplitude: 0.002, period: 0.04}}}
  - {name: shelf, type: plane, point: [0, 0, 0.002], normal: [0.2, 0, 1], material: wall}
particles:
  - {material: grain, shape: rod.yaml, count: 14, velocity: [0.1, 0, -0.6],
     region: {min: [0.002, 0.002, 0.0], max: [0.038, 0.028, 0.016]}}
  - {material: grain, diameter: 0.003, diameter_spread: 0.1, count: 60, velocity: [0, 0, -0.6],
     region: {min: [0.001, 0.001, 0.016], max: [0.039, 0.029, 0.045]}}
  - {material: grain, diameter: 0.0032, mass: 0.0012, rate: 0.012, start: 0.002,
     region: {min: [0.003, 0.001, 0.045], max: [0.037, 0.029, 0.059]}}
output: {directory: out, snapshot_interval: 0.01, checkpoint_interval: 0.02}
)";
}

/// A running `grainscale dem` process; its stdout and stderr go to `console`.
class DemProcess {
 public:
  DemProcess(const TempDir& dir, const std::string& out, int threads, bool resume) {
    std::vector<std::string> args{GRAINSCALE_BINARY, "dem", dir / "scenario.yaml", "--out", out, "--threads",
                                  std::to_string(threads)};
    if (resume) args.push_back("--resume");
    const std::string console = out + ".console.txt";
    pid_ = fork();
    REQUIRE(pid_ >= 0);
    if (pid_ == 0) {
      std::FILE* f = std::fopen(console.c_str(), "a");
      if (f == nullptr) _exit(120);
      dup2(fileno(f), 1);
      dup2(fileno(f), 2);
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(121);
    }
  }
  ~DemProcess() {
    if (pid_ > 0 && !reaped_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  /// Non-blocking: has it ended (and how)?
  bool ended() {
    if (reaped_) return true;
    if (waitpid(pid_, &status_, WNOHANG) == pid_) reaped_ = true;
    return reaped_;
  }
  /// Wait for the end, at most `limit`; kills it and fails if it takes longer.
  int wait(std::chrono::seconds limit) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (!ended()) {
      if (std::chrono::steady_clock::now() > until) {
        kill(pid_, SIGKILL);
        FAIL("grainscale dem did not finish within " << limit.count() << " s");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return status_;
  }
  void kill_now() {
    REQUIRE(::kill(pid_, SIGKILL) == 0);
    waitpid(pid_, &status_, 0);
    reaped_ = true;
  }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool reaped_ = false;
};

/// Poll until `out`/checkpoint.h5 holds a state past step `after` (a checkpoint is renamed into place
/// whole, so one that exists can be read); returns that step. Fails if the process ends first or
/// nothing appears within a minute.
std::uint64_t wait_for_checkpoint(DemProcess& p, const std::string& out, std::uint64_t after) {
  const std::string file = out + "/checkpoint.h5";
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until) {
    if (p.ended()) FAIL("grainscale dem ended before a checkpoint past step " << after << " appeared:\n" << slurp(out + ".console.txt"));
    struct stat st {};
    if (::stat(file.c_str(), &st) == 0) {
      const grainscale::dem::CheckpointInfo info = grainscale::dem::read_checkpoint_info(file);
      if (info.step > after) return info.step;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  FAIL("no checkpoint past step " << after << " within 60 s");
  return 0;
}

/// Kill `p` a few milliseconds (`delay_ms`) after a checkpoint past step `after` exists; checks the run
/// had not finished. Returns the step of the last checkpoint on disk.
std::uint64_t kill_after_checkpoint(DemProcess& p, const std::string& out, std::uint64_t after, int delay_ms) {
  wait_for_checkpoint(p, out, after);
  std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
  const bool finished_first = p.ended();
  if (!finished_first) p.kill_now();
  INFO(slurp(out + ".console.txt"));
  REQUIRE_FALSE(finished_first);  // the machine was so slow that the whole run ended within delay_ms
  const grainscale::dem::CheckpointInfo info = grainscale::dem::read_checkpoint_info(out + "/checkpoint.h5");
  REQUIRE_FALSE(info.complete);
  REQUIRE_FALSE(fs::exists(out + "/summary.yaml"));
  return info.step;
}

/// summary.yaml without the lines that measure wall-clock time.
std::string summary_without_wall_clock(const std::string& out) {
  std::istringstream in(slurp(out + "/summary.yaml"));
  std::string kept, line;
  while (std::getline(in, line)) {
    if (line.rfind("wall_clock_s:", 0) == 0 || line.rfind("sphere_steps_per_s:", 0) == 0) continue;
    kept += line + "\n";
  }
  return kept;
}

std::vector<std::string> files_under(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) names.push_back(fs::relative(e.path(), dir).string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST_CASE("grainscale dem killed with SIGKILL twice and resumed ends byte-identical to an uninterrupted run",
          "[studies][resume][kill]") {
  const TempDir dir;
  write_scenario(dir);
  const std::string whole = dir / "whole", killed = dir / "killed";

  {
    DemProcess reference(dir, whole, 1, false);
    const int status = reference.wait(std::chrono::seconds(120));
    INFO(slurp(whole + ".console.txt"));
    REQUIRE(status == 0);
  }

  // Killed some milliseconds after its first checkpoint, on one thread ...
  std::uint64_t step = 0;
  {
    DemProcess p(dir, killed, 1, false);
    step = kill_after_checkpoint(p, killed, 0, 7);
  }
  // ... resumed on two threads and killed again once that run has checkpointed further on ...
  {
    DemProcess p(dir, killed, 2, true);
    const std::uint64_t before = step;
    step = kill_after_checkpoint(p, killed, before + 64, 3);
    CHECK(step > before);
  }
  // ... and resumed to the end on one thread.
  {
    DemProcess p(dir, killed, 1, true);
    INFO(slurp(killed + ".console.txt"));
    REQUIRE(p.wait(std::chrono::seconds(120)) == 0);
  }

  const std::string log = slurp(killed + "/log.txt");
  CHECK(log.find("resumed from") != std::string::npos);

  // The same files (no .tmp left by a kill during a write), with the same bytes.
  std::vector<std::string> names = files_under(whole + "/snapshots");
  REQUIRE(names.size() == 16);  // t = 0, 0.01, ..., 0.14 and the end
  CHECK(files_under(killed + "/snapshots") == names);
  for (const std::string& n : names) {
    INFO(n);
    CHECK(slurp(whole + "/snapshots/" + n) == slurp(killed + "/snapshots/" + n));
  }
  CHECK(files_under(killed) == files_under(whole));
  CHECK(slurp(whole + "/snapshots.xmf") == slurp(killed + "/snapshots.xmf"));
  const std::string summary = summary_without_wall_clock(whole);
  CHECK(summary.find("snapshots: 16") != std::string::npos);
  CHECK(summary_without_wall_clock(killed) == summary);
}
