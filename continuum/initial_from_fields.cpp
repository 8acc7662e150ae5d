#include "continuum/initial_from_fields.hpp"

#include <algorithm>
#include <cmath>

#include "continuum/cg_section.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

std::vector<double> initial_from_cg_frame(const std::string& path, int frame, double min_solid_fraction, const Grid& g) {
  CgSection f;
  try {
    f = read_cg_section(path, frame);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (initial.file, initial.frame = " + std::to_string(frame) + ")");
  }
  const std::size_t nx = f.x.size(), nz = f.z.size();
  auto is_bed = [&](std::size_t k, std::size_t j) { return std::isfinite(f.c_at(k, j)) && f.phi_at(k, j) >= min_solid_fraction; };
  std::vector<bool> has_bed(nx, false);
  for (std::size_t j = 0; j < nx; ++j)
    for (std::size_t k = 0; k < nz; ++k) has_bed[j] = has_bed[j] || is_bed(k, j);
  if (std::none_of(has_bed.begin(), has_bed.end(), [](bool b) { return b; })) {
    throw InputError(path + ": initial.frame = " + std::to_string(frame) + ": no cell with solid fraction >= " +
                     std::to_string(min_solid_fraction) + " (initial.min_solid_fraction)");
  }
  std::vector<double> out(g.cells(), 0.0);
  for (int i = 0; i < g.nx(); ++i) {
    // The nearest column with bed cells (ties: the lower x).
    std::size_t best = nx;
    for (std::size_t j = 0; j < nx; ++j) {
      if (has_bed[j] && (best == nx || std::abs(f.x[j] - g.x_centre(i)) < std::abs(f.x[best] - g.x_centre(i)))) best = j;
    }
    for (int k = 0; k < g.nz(); ++k) {
      const double z = g.z_centre(i, k);
      std::size_t kk = nz;
      for (std::size_t l = 0; l < nz; ++l) {
        if (is_bed(l, best) && (kk == nz || std::abs(f.z[l] - z) < std::abs(f.z[kk] - z))) kk = l;
      }
      out[g.index(i, k)] = std::clamp(f.c_at(kk, best), 0.0, 1.0);
    }
  }
  return out;
}

}  // namespace grainscale::continuum
