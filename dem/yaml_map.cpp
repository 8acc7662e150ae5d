#include "dem/yaml_map.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

namespace grainscale {

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string Range::describe() const {
  std::ostringstream s;
  s << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
  return s.str();
}

YamlMap YamlMap::load_file(const std::string& file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw InputError(file + ": cannot open file");
  } catch (const YAML::Exception& e) {
    throw InputError(file + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  if (!root.IsMap()) throw InputError(file + ": the top level must be a mapping (key: value)");
  return YamlMap(root, file, "");
}

YamlMap::YamlMap(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {
  if (!node_.IsMap()) {
    throw InputError(file_ + ":" + std::to_string(node_.Mark().line + 1) + ": '" + path_ +
                     "' must be a mapping (key: value)");
  }
}

std::string YamlMap::key_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

std::string YamlMap::where(const std::string& key) const {
  int line = node_.Mark().line;
  if (node_[key]) line = node_[key].Mark().line;
  return file_ + ":" + std::to_string(line + 1) + ": key '" + key_path(key) + "'";
}

bool YamlMap::has(const std::string& key) const { return static_cast<bool>(node_[key]); }

const YAML::Node& YamlMap::require(const std::string& key) {
  read_.insert(key);
  YAML::Node n = node_[key];
  if (!n) {
    throw InputError(file_ + ":" + std::to_string(node_.Mark().line + 1) + ": missing required key '" +
                     key_path(key) + "'");
  }
  keep_.push_back(n);
  return keep_.back();
}

double YamlMap::to_number(const YAML::Node& n, const std::string& key) const {
  if (!n.IsScalar()) throw InputError(where(key) + " must be a number");
  try {
    return n.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(where(key) + " must be a number, got '" + n.Scalar() + "'");
  }
}

double YamlMap::number(const std::string& key, Range range) {
  const double v = to_number(require(key), key);
  if (!range.contains(v)) {
    std::ostringstream s;
    s << where(key) << " = " << v << " is out of range; allowed " << range.describe();
    throw InputError(s.str());
  }
  return v;
}

double YamlMap::number_or(const std::string& key, double fallback, Range range) {
  return has(key) ? number(key, range) : (read_.insert(key), fallback);
}

long YamlMap::integer(const std::string& key, long lo, long hi) {
  const YAML::Node& n = require(key);
  long v = 0;
  try {
    v = n.as<long>();
  } catch (const YAML::Exception&) {
    throw InputError(where(key) + " must be an integer, got '" + (n.IsScalar() ? n.Scalar() : "?") + "'");
  }
  if (v < lo || v > hi) {
    throw InputError(where(key) + " = " + std::to_string(v) + " is out of range; allowed [" + std::to_string(lo) +
                     ", " + std::to_string(hi) + "]");
  }
  return v;
}

long YamlMap::integer_or(const std::string& key, long fallback, long lo, long hi) {
  return has(key) ? integer(key, lo, hi) : (read_.insert(key), fallback);
}

bool YamlMap::boolean_or(const std::string& key, bool fallback) {
  if (!has(key)) return read_.insert(key), fallback;
  const YAML::Node& n = require(key);
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    throw InputError(where(key) + " must be true or false");
  }
}

std::string YamlMap::string(const std::string& key) {
  const YAML::Node& n = require(key);
  if (!n.IsScalar()) throw InputError(where(key) + " must be a string");
  return n.Scalar();
}

std::string YamlMap::string_or(const std::string& key, const std::string& fallback) {
  return has(key) ? string(key) : (read_.insert(key), fallback);
}

std::string YamlMap::choice(const std::string& key, const std::vector<std::string>& allowed) {
  const std::string v = string(key);
  for (const auto& a : allowed) {
    if (a == v) return v;
  }
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  throw InputError(where(key) + " = '" + v + "' is not allowed; choose one of: " + list);
}

std::string YamlMap::choice_or(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& allowed) {
  return has(key) ? choice(key, allowed) : (read_.insert(key), fallback);
}

std::vector<std::string> YamlMap::choices_or_empty(const std::string& key, const std::vector<std::string>& allowed) {
  std::vector<std::string> out;
  if (!has(key)) return read_.insert(key), out;
  const YAML::Node& n = require(key);
  if (!n.IsSequence()) throw InputError(where(key) + " must be a list, e.g. [" + allowed.front() + "]");
  for (const auto& item : n) {
    const std::string v = item.IsScalar() ? item.Scalar() : std::string("?");
    bool ok = false;
    for (const auto& a : allowed) ok = ok || a == v;
    if (!ok) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw InputError(where(key) + ": '" + v + "' is not allowed; choose from: " + list);
    }
    out.push_back(v);
  }
  return out;
}

std::vector<double> YamlMap::numbers_or_empty(const std::string& key, std::size_t min_count, std::size_t max_count,
                                              Range range) {
  std::vector<double> out;
  if (!has(key)) return read_.insert(key), out;
  const YAML::Node& n = require(key);
  if (!n.IsSequence() || n.size() < min_count || n.size() > max_count) {
    throw InputError(where(key) + " must be a list of " + std::to_string(min_count) + " to " + std::to_string(max_count) +
                     " numbers");
  }
  for (std::size_t i = 0; i < n.size(); ++i) {
    const double v = to_number(n[i], key);
    if (!range.contains(v)) {
      std::ostringstream s;
      s << where(key) << " item " << i << " = " << v << " is out of range; allowed " << range.describe();
      throw InputError(s.str());
    }
    out.push_back(v);
  }
  return out;
}

dem::Vec3 YamlMap::vec3(const std::string& key, Range r) {
  const YAML::Node& n = require(key);
  if (!n.IsSequence() || n.size() != 3) throw InputError(where(key) + " must be a list of 3 numbers [x, y, z]");
  double c[3];
  for (int i = 0; i < 3; ++i) {
    c[i] = to_number(n[i], key);
    if (!r.contains(c[i])) {
      std::ostringstream s;
      s << where(key) << " component " << i << " = " << c[i] << " is out of range; allowed " << r.describe();
      throw InputError(s.str());
    }
  }
  return {c[0], c[1], c[2]};
}

dem::Vec3 YamlMap::vec3_or(const std::string& key, dem::Vec3 fallback, Range r) {
  return has(key) ? vec3(key, r) : (read_.insert(key), fallback);
}

YamlMap YamlMap::map(const std::string& key) {
  const YAML::Node& n = require(key);
  if (!n.IsMap()) throw InputError(where(key) + " must be a mapping (key: value)");
  return YamlMap(n, file_, key_path(key));
}

std::optional<YamlMap> YamlMap::optional_map(const std::string& key) {
  if (!has(key)) return read_.insert(key), std::nullopt;
  return map(key);
}

std::vector<YamlMap> YamlMap::list_of_maps(const std::string& key) {
  const YAML::Node& n = require(key);
  if (!n.IsSequence()) throw InputError(where(key) + " must be a list");
  std::vector<YamlMap> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string p = key_path(key) + "[" + std::to_string(i) + "]";
    if (!n[i].IsMap()) {
      throw InputError(file_ + ":" + std::to_string(n[i].Mark().line + 1) + ": '" + p + "' must be a mapping");
    }
    out.emplace_back(n[i], file_, p);
  }
  return out;
}

std::string YamlMap::key_of(const YAML::Node& key) const {
  // YAML allows any node as a key ({a: 1}: x, [1, 2]: x); every key here is a plain word.
  if (!key.IsScalar()) {
    throw InputError(file_ + ":" + std::to_string(key.Mark().line + 1) + ": a key in '" +
                     (path_.empty() ? std::string("the top level") : path_) + "' is not a plain word");
  }
  return key.Scalar();
}

std::vector<std::string> YamlMap::keys() const {
  std::vector<std::string> k;
  for (const auto& kv : node_) k.push_back(key_of(kv.first));
  return k;
}

void YamlMap::finish() const {
  for (const auto& kv : node_) {
    const std::string k = key_of(kv.first);
    if (!read_.count(k)) {
      throw InputError(file_ + ":" + std::to_string(kv.first.Mark().line + 1) + ": unknown key '" + key_path(k) +
                       "' (misspelt, or not valid here)");
    }
  }
}

std::string resolve_beside(const std::string& base_file, const std::string& relative) {
  namespace fs = std::filesystem;
  fs::path p(relative);
  if (p.is_absolute()) return p.string();
  return (fs::path(base_file).parent_path() / p).lexically_normal().string();
}

}  // namespace grainscale
