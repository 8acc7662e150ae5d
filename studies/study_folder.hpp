#pragma once
// The folder every study writes (docs/studies.md): `inputs/` (the study file and the files it names,
// copied as run), `log.txt` (every stage's start, end, wall clock and result, also echoed to the
// terminal), and whatever the study's stages put beside them. Shared by every study kind so that each
// kind's folder looks the same to a user.
#include <fstream>
#include <string>
#include <vector>

namespace grainscale::studies {

class StudyFolder {
 public:
  /// Creates `directory` (and `inputs/`), opens `log.txt` (appending when `resume`), copies `inputs`
  /// into `inputs/`. Throws std::runtime_error naming the path when the folder cannot be written.
  StudyFolder(const std::string& directory, const std::vector<std::string>& inputs, bool resume = false);

  /// Absolute path of `relative` inside the folder.
  std::string path(const std::string& relative) const;
  const std::string& directory() const { return dir_; }

  /// A line into log.txt and onto stderr as "[study] line".
  void log(const std::string& line);

  /// Copies one more input file into inputs/ (e.g. a file named by a file the study names).
  void copy_input(const std::string& file);

 private:
  std::string dir_;
  std::ofstream log_;
};

/// Seconds on a monotonic clock (for a stage's wall clock).
double wall_seconds_now();

}  // namespace grainscale::studies
