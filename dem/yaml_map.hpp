#pragma once
// Checked access to one YAML mapping. Each getter validates type and range and throws InputError
// naming file, line and the full key path (e.g. "box.yaml:14: key 'walls[2].radius' ..."). Keys
// that were never read are reported by finish(), so a typo like `resitution:` cannot pass silently.
#include <yaml-cpp/yaml.h>

#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "dem/input_error.hpp"
#include "dem/vec3.hpp"

namespace grainscale {

/// Allowed interval for a number; open or closed at each end.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static Range positive() { return {0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  bool contains(double v) const;
  std::string describe() const;  // e.g. "(0, 1]"
};

class YamlMap {
 public:
  /// Parse a file whose top level is a mapping. Throws InputError if missing or malformed.
  static YamlMap load_file(const std::string& file);
  YamlMap(YAML::Node node, std::string file, std::string path);

  bool has(const std::string& key) const;
  double number(const std::string& key, Range range = {});
  double number_or(const std::string& key, double fallback, Range range = {});
  long integer(const std::string& key, long lo, long hi);
  long integer_or(const std::string& key, long fallback, long lo, long hi);
  bool boolean_or(const std::string& key, bool fallback);
  std::string string(const std::string& key);
  std::string string_or(const std::string& key, const std::string& fallback);
  /// A string that must be one of `allowed`.
  std::string choice(const std::string& key, const std::vector<std::string>& allowed);
  std::string choice_or(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed);
  /// A list of strings, each one of `allowed`; empty if the key is absent.
  std::vector<std::string> choices_or_empty(const std::string& key, const std::vector<std::string>& allowed);
  /// A list of min_count..max_count numbers, each in `range`; empty if the key is absent.
  std::vector<double> numbers_or_empty(const std::string& key, std::size_t min_count, std::size_t max_count,
                                       Range range = {});
  dem::Vec3 vec3(const std::string& key, Range component_range = {});
  dem::Vec3 vec3_or(const std::string& key, dem::Vec3 fallback, Range component_range = {});
  YamlMap map(const std::string& key);
  std::optional<YamlMap> optional_map(const std::string& key);
  std::vector<YamlMap> list_of_maps(const std::string& key);
  /// Keys of this mapping in file order (for maps keyed by name, like materials).
  std::vector<std::string> keys() const;

  /// Throw if the mapping holds keys that were never read.
  void finish() const;

  /// "file:line: key 'path.key'" for messages built by callers (e.g. cross-key checks).
  std::string where(const std::string& key) const;
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

 private:
  const YAML::Node& require(const std::string& key);
  std::string key_path(const std::string& key) const;
  double to_number(const YAML::Node& n, const std::string& key) const;
  std::string key_of(const YAML::Node& key) const;  // InputError unless a plain (scalar) key

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::set<std::string> read_;
  std::vector<YAML::Node> keep_;  // yaml-cpp nodes are handles; keep children alive
};

/// Resolve `relative` against the directory of `base_file` (absolute paths pass through).
std::string resolve_beside(const std::string& base_file, const std::string& relative);

}  // namespace grainscale
