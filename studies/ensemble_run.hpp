#pragma once
// `grainscale study FILE.yaml` for `kind: ensemble` (studies/ensemble_settings.hpp): every variant
// run over every seed, read as the algorithm -
//   setup();   output folder, inputs copied, log.txt opened
//   run();     for each variant, for each seed ("run 3/8: variant split, seed 2"):
//                scenario.yaml   the variant's scenario with the seed (and scale) replaced
//                dem/            grainscale dem (checkpointed; --resume continues or skips it)
//                cg/             grainscale cg on its snapshots (cg.yaml beside it)
//                aor/            the angle-of-repose test at the variant's scale (optional)
//                measures        studies/ensemble_measures.hpp, written to measures.csv
//   output();  per-variant mean, sd and n; differences with Welch intervals; figures; report.md
// A run folder is runs/<variant>/seed_<seed>/ and holds ordinary stage files: `grainscale dem
// runs/v/seed_1/scenario.yaml` and `grainscale cg runs/v/seed_1/cg.yaml` repeat one run.
// With --resume, a run whose scenario is unchanged and whose DEM finished (summary.yaml, complete
// checkpoint) is not run again; an unfinished one continues from its checkpoint.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "studies/ensemble_measures.hpp"
#include "studies/ensemble_settings.hpp"
#include "studies/study_folder.hpp"
#include "studies/study_run.hpp"

namespace grainscale::studies {

/// One variant x seed.
struct EnsembleRunRecord {
  std::string variant;
  std::uint64_t seed = 0;
  std::string folder;          // relative to the study folder
  std::string status;          // "ran", "resumed", "kept" (finished earlier, --resume)
  double scale_factor = 1;
  std::map<std::string, std::string> dem_summary;  // summary.yaml's scalar entries
  double wall_seconds = 0;     // this run's DEM + cg + AOR, including time before a resume
  RunMeasures measures;
  double aor_deg = 0, aor_spread_deg = 0;  // NaN without an AOR test (or when it failed)
};

struct EnsembleResults {
  std::vector<EnsembleRunRecord> runs;
  std::vector<std::string> warnings;
  double wall_seconds = 0;
};

class EnsembleRun {
 public:
  EnsembleRun(EnsembleSettings settings, StudyOptions options);
  void setup();
  void run();
  void output();
  const EnsembleResults& results() const { return results_; }
  const EnsembleSettings& settings() const { return s_; }
  const std::string& output_directory() const { return out_; }

  /// Folder of one run, relative to the study folder.
  static std::string run_folder(const std::string& variant, std::uint64_t seed);

 private:
  EnsembleRunRecord run_one(const EnsembleVariant& v, std::uint64_t seed, const std::string& progress);
  void aor(const EnsembleVariant& v, EnsembleRunRecord& r);
  void log(const std::string& line);
  std::string path(const std::string& relative) const;

  EnsembleSettings s_;
  StudyOptions o_;
  std::string out_;
  std::optional<StudyFolder> folder_;
  EnsembleResults results_;
};

/// The `ensemble` kind's runner (study_kinds.cpp): returns the report's path.
std::string run_ensemble_study(const std::string& study_file, const StudyOptions& options);

}  // namespace grainscale::studies
