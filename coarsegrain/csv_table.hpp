#pragma once
// A numeric CSV table: a header line of column names, then rows of numbers written with 17
// significant digits (round-trip exact; NaN as "nan"). Used for the profiles the continuum stage and
// the measured data share (t_s,x_m,z_m,c for fields; t_s,x_m,coverage for top-view profiles).
#include <string>
#include <vector>

namespace grainscale::cg {

class CsvTable {
 public:
  explicit CsvTable(std::vector<std::string> columns);
  /// Append a row; std::invalid_argument if it has the wrong number of values.
  void row(const std::vector<double>& values);
  std::size_t rows() const { return rows_; }
  const std::string& text() const { return text_; }
  /// Write atomically (dem/atomic_file.hpp).
  void write(const std::string& path) const;

 private:
  std::size_t columns_;
  std::size_t rows_ = 0;
  std::string text_;
};

}  // namespace grainscale::cg
