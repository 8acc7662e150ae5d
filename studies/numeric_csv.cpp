#include "studies/numeric_csv.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>

#include "dem/input_error.hpp"

namespace grainscale::studies {

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string item;
  std::stringstream in(line);
  while (std::getline(in, item, ',')) out.push_back(trim(item));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

/// Locale-independent: from_chars, plus a leading '+' that it does not take.
bool to_number(const std::string& s, double& v) {
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

}  // namespace

NumericCsv NumericCsv::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the CSV file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path);
}

NumericCsv NumericCsv::parse(const std::string& text, const std::string& name) {
  NumericCsv t;
  t.name_ = name;
  std::stringstream in(text);
  std::string line;
  int number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    const std::vector<std::string> fields = split(s);
    const std::string where = name + ":" + std::to_string(number);
    if (!header) {
      for (const auto& f : fields) {
        if (f.empty()) throw InputError(where + ": empty column name in the header");
        if (std::count(t.columns_.begin(), t.columns_.end(), f)) throw InputError(where + ": column '" + f + "' appears twice");
        t.columns_.push_back(f);
      }
      t.data_.resize(t.columns_.size());
      header = true;
      continue;
    }
    if (fields.size() != t.columns_.size()) {
      throw InputError(where + ": " + std::to_string(fields.size()) + " values for " + std::to_string(t.columns_.size()) +
                       " columns");
    }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      double v = 0;
      if (!to_number(fields[k], v)) {
        throw InputError(where + ": column '" + t.columns_[k] + "': '" + fields[k] + "' is not a number");
      }
      t.data_[k].push_back(v);
    }
    t.lines_.push_back(number);
    ++t.rows_;
  }
  if (!header) throw InputError(name + ": no header line (expected column names, e.g. t_s,x_m,...)");
  return t;
}

bool NumericCsv::has(const std::string& column) const {
  return std::find(columns_.begin(), columns_.end(), column) != columns_.end();
}

std::vector<double> NumericCsv::column(const std::string& c) const {
  const auto it = std::find(columns_.begin(), columns_.end(), c);
  if (it == columns_.end()) {
    std::string have;
    for (const auto& n : columns_) have += (have.empty() ? "" : ", ") + n;
    throw InputError(name_ + ": no column '" + c + "' (it has: " + have + ")");
  }
  return data_[static_cast<std::size_t>(it - columns_.begin())];
}

}  // namespace grainscale::studies
