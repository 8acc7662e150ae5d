#include "coarsegrain/csv_table.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "dem/atomic_file.hpp"

namespace grainscale::cg {

CsvTable::CsvTable(std::vector<std::string> columns) : columns_(columns.size()) {
  for (std::size_t k = 0; k < columns.size(); ++k) text_ += (k ? "," : "") + columns[k];
  text_ += '\n';
}

void CsvTable::row(const std::vector<double>& values) {
  if (values.size() != columns_) throw std::invalid_argument("CsvTable::row: wrong number of values");
  char buf[32];
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k) text_ += ',';
    if (std::isnan(values[k])) {
      text_ += "nan";
    } else {
      std::snprintf(buf, sizeof buf, "%.17g", values[k]);
      text_ += buf;
    }
  }
  text_ += '\n';
  ++rows_;
}

void CsvTable::write(const std::string& path) const { dem::write_file_atomically(path, text_); }

}  // namespace grainscale::cg
