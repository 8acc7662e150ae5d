// `grainscale dem --resume` (dem/dem_run.hpp): a run stopped right after a checkpoint, as a kill
// would stop it, and resumed ends with the same files, byte for byte, as a run never stopped; a
// changed scenario is refused; a blow-up keeps the last good checkpoint; a failed write stops the run
// with an error naming the path and leaves earlier output intact.
#include <hdf5.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "checkpoint_fixture.hpp"
#include "run_and_stop.hpp"
#include "dem/checkpoint.hpp"
#include "dem/dem_run.hpp"
#include "dem/input_error.hpp"
#include "dem/snapshot.hpp"
#include "grainscale_version.hpp"

using namespace grainscale;
using namespace grainscale::dem;
using Catch::Matchers::Contains;
using testing::run_to_end;
using testing::run_until_checkpoint;
namespace fs = std::filesystem;

namespace {

// 0.03 s: about 1200 steps, snapshots at 0, 0.01, 0.02 and the end; a checkpoint every 64 steps.
constexpr double kEnd = 0.03;
const std::string kOften = "checkpoint_interval: 1.0e-9";

std::vector<std::string> snapshot_names(const std::string& out) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(fs::path(out) / "snapshots")) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// Rewrite the root attribute `code_version` of a checkpoint, as another build would have written it.
void set_code_version(const std::string& file, const std::string& value) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  REQUIRE(f >= 0);
  REQUIRE(H5Adelete(f, "code_version") >= 0);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(f, "code_version", type, space, H5P_DEFAULT, H5P_DEFAULT);
  const char* p = value.c_str();
  REQUIRE(H5Awrite(a, type, &p) >= 0);
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
  REQUIRE(H5Fclose(f) >= 0);
}

/// Same snapshot files with the same bytes, and the same XDMF series.
void require_same_output(const std::string& a, const std::string& b) {
  const std::vector<std::string> names = snapshot_names(a);
  REQUIRE(names.size() >= 3);
  CHECK(snapshot_names(b) == names);
  for (const std::string& n : names) {
    INFO(n);
    CHECK(testing::slurp_file(a + "/snapshots/" + n) == testing::slurp_file(b + "/snapshots/" + n));
  }
  CHECK(testing::slurp_file(a + "/snapshots.xmf") == testing::slurp_file(b + "/snapshots.xmf"));
}

}  // namespace

TEST_CASE("A run stopped after a checkpoint and resumed ends byte-identical to one never stopped",
          "[dem][checkpoint][resume]") {
  const testing::CheckpointTempDir dir;
  // The same scenario twice, checkpointing every 64 steps or (by default) every 10 minutes: the
  // interval changes nothing but when checkpoints are written.
  const std::string often = testing::write_checkpoint_scenario(dir, kEnd, kOften, "often.yaml");
  const std::string scenario = testing::write_checkpoint_scenario(dir, kEnd);
  run_to_end(scenario, dir / "whole");

  // Stopped after the 7th checkpoint (step 448, t = 0.011 s): one snapshot after t = 0 is on disk.
  run_until_checkpoint(often, dir / "stopped", 7);
  const CheckpointInfo info = read_checkpoint_info(dir / "stopped/checkpoint.h5");
  CHECK(info.step == 7 * 64);
  CHECK_FALSE(info.complete);
  CHECK(fs::exists(dir / "stopped/snapshots/snap_000001.h5"));
  CHECK_FALSE(fs::exists(dir / "stopped/summary.yaml"));

  // Forgetting --resume would overwrite the only way back: refused.
  CHECK_THROWS_WITH(run_to_end(scenario, dir / "stopped"), Contains("unfinished run") && Contains("--resume"));

  run_to_end(scenario, dir / "stopped", true);
  require_same_output(dir / "whole", dir / "stopped");
  const std::string log = testing::slurp_file(dir / "stopped/log.txt");
  CHECK_THAT(log, Contains("resumed from") && Contains("step 448"));
  CHECK(read_checkpoint_info(dir / "stopped/checkpoint.h5").complete);

  // A finished run may be extended: raise the end time and resume; the same as running that far.
  testing::write_checkpoint_scenario(dir, kEnd + 0.01);
  run_to_end(scenario, dir / "stopped", true);
  run_to_end(scenario, dir / "longer");
  require_same_output(dir / "longer", dir / "stopped");
}

TEST_CASE("Resuming is refused without a checkpoint or with a scenario that changes the dynamics",
          "[dem][checkpoint][resume]") {
  const testing::CheckpointTempDir dir;
  const std::string scenario = testing::write_checkpoint_scenario(dir, kEnd, kOften);
  CHECK_THROWS_WITH(run_to_end(scenario, dir / "out", true),
                    Contains("no checkpoint") && Contains(dir / "out/checkpoint.h5"));
  run_until_checkpoint(scenario, dir / "out", 2);
  // An unreadable checkpoint in the way of a fresh start: refused too, saying what to do.
  fs::create_directories(dir / "garbled");
  std::ofstream(dir / "garbled/checkpoint.h5") << "not a checkpoint";
  CHECK_THROWS_WITH(run_to_end(scenario, dir / "garbled"), Contains("not an HDF5 file") && Contains("delete it"));

  // Another friction coefficient: the first differing fingerprint line is quoted, old and new.
  std::string materials = testing::kCheckpointMaterials;
  materials.replace(materials.find("friction: 0.5"), 13, "friction: 0.6");
  std::ofstream(dir / "materials.yaml") << materials;
  CHECK_THROWS_AS(run_to_end(scenario, dir / "out", true), InputError);
  CHECK_THROWS_WITH(run_to_end(scenario, dir / "out", true),
                    Contains("pairs.grain-grain") && Contains("mu 0.5,") && Contains("mu 0.6,"));
  std::ofstream(dir / "materials.yaml") << testing::kCheckpointMaterials;

  // Another wall motion.
  std::string moved = testing::checkpoint_scenario(kEnd, kOften);
  moved.replace(moved.find("period: 0.04"), 12, "period: 0.05");
  std::ofstream(dir / "scenario.yaml") << moved;
  CHECK_THROWS_WITH(run_to_end(scenario, dir / "out", true), Contains("walls[0].motion"));
  // Another release wrote it: refused; the same release at another revision: a warning, and on.
  std::ofstream(dir / "scenario.yaml") << testing::checkpoint_scenario(kEnd, kOften);
  const std::string checkpoint = dir / "out/checkpoint.h5";
  const std::string saved = testing::slurp_file(checkpoint);
  set_code_version(checkpoint, "0.0.1 0123abc");
  CHECK_THROWS_WITH(run_to_end(scenario, dir / "out", true), Contains("0.0.1 0123abc") && Contains("another release"));
  std::ofstream(checkpoint, std::ios::binary) << saved;
  set_code_version(checkpoint, std::string(grainscale::version) + " 0123abc");
  // Output settings may change.
  testing::write_checkpoint_scenario(dir, kEnd, "progress_interval: 3");
  run_to_end(scenario, dir / "out", true);
  CHECK_THAT(testing::slurp_file(dir / "out/log.txt"), Contains("warning: the checkpoint was written by grainscale " +
                                                                std::string(grainscale::version) + " 0123abc"));
}

TEST_CASE("A blow-up stops the run and keeps the last good checkpoint and the snapshots",
          "[dem][checkpoint][resume]") {
  const testing::CheckpointTempDir dir;
  std::string text = testing::checkpoint_scenario(kEnd, kOften);
  // An overlap limit of 20 % of the radius, which this bed first exceeds after some 300 steps (the
  // default 30 % it never reaches): a "blow-up" after a few checkpoints.
  text.replace(text.find("contact: {rolling: epsd}"), 24, "contact: {rolling: epsd, max_overlap: 0.2}");
  std::ofstream(dir / "materials.yaml") << testing::kCheckpointMaterials;
  std::ofstream(dir / "scenario.yaml") << text;

  DemRun r(dir / "scenario.yaml", dir / "out");
  std::string last_good;
  r.on_checkpoint([&](const std::string& path) { last_good = testing::slurp_file(path); });
  r.setup();
  std::string message;
  try {
    r.run();
  } catch (const BlowUp& e) {
    message = e.what();
  }
  REQUIRE_FALSE(message.empty());
  REQUIRE_FALSE(last_good.empty());  // checkpoints were written before it blew up
  CHECK_THAT(message, Contains("overlap") && Contains("last good checkpoint") && Contains(dir / "out/checkpoint.h5"));
  CHECK(testing::slurp_file(dir / "out/checkpoint.h5") == last_good);
  CHECK_FALSE(fs::exists(dir / "out/checkpoint.h5.tmp"));
  CHECK(read_checkpoint_info(dir / "out/checkpoint.h5").time < r.simulation().time());
  CHECK(read_snapshot(dir / "out/snapshots/snap_000000.h5").time == 0);
  CHECK_THAT(testing::slurp_file(dir / "out/log.txt"), Contains("blow-up"));
}

TEST_CASE("A failed write ends the run with an error naming the path; earlier output stays intact",
          "[dem][checkpoint][resume]") {
  const testing::CheckpointTempDir dir;
  const std::string scenario = testing::write_checkpoint_scenario(dir, kEnd, kOften);
  const std::string out = dir / "out";
  testing::write_checkpoint_scenario(dir, kEnd, "", "plain.yaml");  // (no checkpoints to speak of)
  std::string kept;  // the checkpoint as it was when writing stopped working

  SECTION("a read-only output folder") {
    // Root ignores permission bits; there the checkpoint's tmp name is blocked by a directory instead
    // (the same failure for the writer: it cannot create its file).
    const bool root = geteuid() == 0;
    DemRun r(scenario, out);
    int written = 0;
    r.on_checkpoint([&](const std::string& path) {
      if (++written != 3) return;
      kept = testing::slurp_file(path);
      if (root) {
        fs::create_directory(path + ".tmp");
      } else {
        fs::permissions(out, fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                        fs::perm_options::remove);
        fs::permissions(out + "/snapshots", fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write,
                        fs::perm_options::remove);
      }
    });
    r.setup();
    CHECK_THROWS_WITH(r.run(), Contains(out + "/checkpoint.h5") && Contains("earlier output") && Contains("intact"));
    if (root) fs::remove(out + "/checkpoint.h5.tmp");
    CHECK(testing::slurp_file(out + "/checkpoint.h5") == kept);
  }
  SECTION("a full disk (a file-size limit that the next write exceeds)") {
    // RLIMIT_FSIZE makes write() fail with EFBIG part-way through a file, as ENOSPC would; SIGXFSZ
    // must be ignored or it would kill the test.
    struct rlimit saved {};
    REQUIRE(getrlimit(RLIMIT_FSIZE, &saved) == 0);
    const auto old_handler = signal(SIGXFSZ, SIG_IGN);
    DemRun r(scenario, out);
    int written = 0;
    r.on_checkpoint([&](const std::string& path) {
      if (++written != 3) return;
      kept = testing::slurp_file(path);
      struct rlimit small = saved;
      small.rlim_cur = 4096;  // below any checkpoint or snapshot
      REQUIRE(setrlimit(RLIMIT_FSIZE, &small) == 0);
    });
    r.setup();
    std::string message;
    try {
      r.run();
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    REQUIRE(setrlimit(RLIMIT_FSIZE, &saved) == 0);
    signal(SIGXFSZ, old_handler);
    CHECK_THAT(message, Contains(out + "/checkpoint.h5") && Contains("File too large") && Contains("intact"));
    CHECK(testing::slurp_file(out + "/checkpoint.h5") == kept);
    for (const auto& e : fs::recursive_directory_iterator(out)) CHECK(e.path().extension() != ".tmp");
    // Not stranded: the run resumes from the kept checkpoint once there is room again.
    run_to_end(dir / "plain.yaml", out, true);
    CHECK(read_checkpoint_info(out + "/checkpoint.h5").complete);
  }
  REQUIRE_FALSE(kept.empty());
  for (const auto& e : fs::recursive_directory_iterator(out)) CHECK(e.path().extension() != ".tmp");
  CHECK(read_snapshot(out + "/snapshots/snap_000000.h5").time == 0);
}

TEST_CASE("Once the pours are done, a run steps in goes that end at every check it makes",
          "[dem][resume]") {
  // DemRun steps as many steps at a time as leave its checks where one step at a time had them
  // (Simulation::run_steps keeps its threads in one region for a go): a checkpoint every 64 steps,
  // and each snapshot at the first step within half a step of its time.
  const testing::CheckpointTempDir dir;
  std::string text = testing::checkpoint_scenario(0.045, kOften);
  const std::size_t pour = text.find("  - {material: grain, diameter: 0.0032");  // no pour: goes from t = 0
  REQUIRE(pour != std::string::npos);
  text.erase(pour, text.find("output:") - pour);
  std::ofstream(dir / "materials.yaml") << testing::kCheckpointMaterials;
  std::ofstream(dir / "goes.yaml") << text;
  DemRun r(dir / "goes.yaml", dir / "goes");
  std::vector<std::uint64_t> checkpoint_steps;
  r.on_checkpoint([&](const std::string& path) { checkpoint_steps.push_back(read_checkpoint_info(path).step); });
  r.setup();
  r.run();
  r.output();
  const double dt = r.simulation().dt(), interval = 0.01;
  const std::uint64_t steps = r.simulation().steps();
  REQUIRE(steps > 1000);
  REQUIRE(checkpoint_steps.size() == steps / 64 + 1);  // and the one at the end
  for (std::size_t k = 0; k + 1 < checkpoint_steps.size(); ++k) CHECK(checkpoint_steps[k] == 64 * (k + 1));
  CHECK(checkpoint_steps.back() == steps);
  const std::string xmf = testing::slurp_file(dir / "goes/snapshots.xmf");
  const std::regex time("<Time Value=\"([^\"]+)\"");
  std::vector<double> times;  // (the particles' and the walls' grids of a snapshot carry its time)
  for (auto m = std::sregex_iterator(xmf.begin(), xmf.end(), time); m != std::sregex_iterator(); ++m) {
    if (times.empty() || std::stod((*m)[1]) != times.back()) times.push_back(std::stod((*m)[1]));
  }
  REQUIRE(times.size() == 6);  // 0, 0.01, ..., 0.04 and the end
  for (int k = 0; k < 5; ++k) {
    INFO("snapshot " << k << " at t = " << times[k] << " s, dt = " << dt << " s");
    CHECK(times[k] >= k * interval - 0.5 * dt);
    CHECK(times[k] < k * interval + 0.5 * dt);
  }
}
