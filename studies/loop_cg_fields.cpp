#include "studies/loop_cg_fields.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "continuum/cg_section.hpp"
#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"

namespace grainscale::studies {

std::size_t cg_fields_to_csv(const std::string& path, const std::string& csv_path) {
  const int frames = continuum::cg_frame_count(path);
  if (frames < 1) throw InputError(path + ": no frames");
  std::ostringstream out;
  std::size_t rows = 0;
  out << "t_s,x_m,z_m,c,phi\n";
  for (int f = 0; f < frames; ++f) {
    const continuum::CgSection s = continuum::read_cg_section(path, f);
    for (std::size_t k = 0; k < s.z.size(); ++k) {
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.c_at(k, i))) continue;  // no particles in this (x, z) cell
        char row[160];
        std::snprintf(row, sizeof row, "%.9g,%.9g,%.9g,%.9g,%.9g\n", s.time, s.x[i], s.z[k], s.c_at(k, i), s.phi_at(k, i));
        out << row;
        ++rows;
      }
    }
  }
  dem::write_file_atomically(csv_path, out.str());
  return rows;
}

}  // namespace grainscale::studies
