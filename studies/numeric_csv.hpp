#pragma once
// A numeric CSV file read back: a header of column names, then rows of numbers ("nan" allowed, as
// coarsegrain/csv_table.hpp writes them). This is how the studies read the stages' profiles and
// measured data (t_s,x_m,z_m,c fields; t_s,x_m,coverage profiles). Blank lines and lines starting
// with '#' are skipped. Every problem is an InputError naming the file, the line and the column.
#include <string>
#include <vector>

namespace grainscale::studies {

class NumericCsv {
 public:
  static NumericCsv load(const std::string& path);
  /// `name` stands for the file in messages.
  static NumericCsv parse(const std::string& text, const std::string& name);

  const std::vector<std::string>& columns() const { return columns_; }
  bool has(const std::string& column) const;
  /// A column's values, one per row; InputError naming the file and the columns it has if absent.
  std::vector<double> column(const std::string& name) const;
  std::size_t rows() const { return rows_; }
  /// Line number of data row `row` in the file (for messages).
  int line(std::size_t row) const { return lines_[row]; }
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> data_;  // per column
  std::vector<int> lines_;                 // per row
  std::size_t rows_ = 0;
};

}  // namespace grainscale::studies
