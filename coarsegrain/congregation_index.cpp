#include "coarsegrain/congregation_index.hpp"

#include <limits>
#include <stdexcept>

namespace grainscale::cg {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ratio(double a, double b) { return b > 0 ? a / b : kNaN; }

/// Coverage of the pixel columns with centre in [a, b).
double zone_coverage(const TopView& v, double a, double b) {
  long occupied = 0, chaff = 0;
  for (int i = 0; i < v.nx; ++i) {
    const double x = v.x(i);
    if (x < a || x >= b) continue;
    for (int j = 0; j < v.ny; ++j) {
      const auto s = v.state[static_cast<std::size_t>(i) + static_cast<std::size_t>(v.nx) * static_cast<std::size_t>(j)];
      occupied += s != TopView::empty;
      chaff += s == TopView::chaff;
    }
  }
  return ratio(static_cast<double>(chaff), static_cast<double>(occupied));
}

}  // namespace

CongregationIndex congregation_index(const CgParticles& p, const SpeciesTable& species, double x_lo, double x_hi,
                                     double end_length, const TopView* view) {
  const double length = x_hi - x_lo;
  if (!(length > 0) || !(end_length > 0) || !(2 * end_length <= length)) {
    throw std::invalid_argument("congregation index: need 0 < 2 end_length <= x_hi - x_lo");
  }
  double chaff[3] = {0, 0, 0}, all[3] = {0, 0, 0};  // left zone, right zone, whole length
  for (std::size_t b = 0; b < p.body_position.size(); ++b) {
    const double x = p.body_position[b].x;
    if (x < x_lo || x > x_hi) continue;
    const bool is_chaff = species.chaff[static_cast<std::size_t>(p.body_species[b])];
    for (int z = 0; z < 3; ++z) {
      const bool in = z == 0 ? x < x_lo + end_length : z == 1 ? x > x_hi - end_length : true;
      if (!in) continue;
      all[z] += 1;
      chaff[z] += is_chaff;
    }
  }
  CongregationIndex ci;
  const double c_all = ratio(chaff[2], all[2]);
  ci.left = ratio(ratio(chaff[0], all[0]), c_all);
  ci.right = ratio(ratio(chaff[1], all[1]), c_all);
  ci.mean = 0.5 * (ci.left + ci.right);
  ci.spread = 0.5 * (ci.right - ci.left);
  const double zone_share = end_length / length;
  ci.share_left = ratio(chaff[0], chaff[2]) / zone_share;
  ci.share_right = ratio(chaff[1], chaff[2]) / zone_share;
  if (view == nullptr) {
    ci.coverage_left = ci.coverage_centre = ci.coverage_right = ci.coverage_ratio = kNaN;
  } else {
    const double mid = 0.5 * (x_lo + x_hi);
    ci.coverage_left = zone_coverage(*view, x_lo, x_lo + end_length);
    ci.coverage_right = zone_coverage(*view, x_hi - end_length, x_hi + 0.5 * view->pixel);
    ci.coverage_centre = zone_coverage(*view, mid - 0.5 * end_length, mid + 0.5 * end_length);
    ci.coverage_ratio = ratio(0.5 * (ci.coverage_left + ci.coverage_right), ci.coverage_centre);
  }
  return ci;
}

}  // namespace grainscale::cg
