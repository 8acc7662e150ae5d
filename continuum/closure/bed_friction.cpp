#include "continuum/closure/bed_friction.hpp"

#include <algorithm>

namespace grainscale::continuum::closure {

namespace {
constexpr double kDeg = M_PI / 180;
}

namespace {

/// (F2) alone.
double mu_bed(const BedFriction& f, double h) {
  const double tphi = std::tan(f.internal_deg * kDeg);
  const double floor = std::min(std::tan(f.basal_deg * kDeg), tphi);
  if (!std::isfinite(f.layer_depth)) return floor;
  return tphi + (floor - tphi) * std::exp(-std::max(h, 0.0) / f.layer_depth);
}

}  // namespace

double BedFriction::mu_static(double h) const {
  if (!side_walls.active()) return mu_bed(*this, h);  // the 2-D closure, unchanged
  return mu_bed(*this, h) + side_walls.mu(active_depth(h));
}

double BedFriction::mu_start(double h) const {
  if (!(start_excess_deg > 0)) return mu_static(h);
  const double excess = std::tan((internal_deg + start_excess_deg) * kDeg) - std::tan(internal_deg * kDeg);
  return mu_static(h) + excess * surface_weight(h);
}

EarthPressure BedFriction::earth_pressure() const {
  return savage_hutter_pressure ? EarthPressure::savage_hutter(internal_deg * kDeg, basal_deg * kDeg)
                                : EarthPressure::hydrostatic();
}

double BedFriction::surface_weight(double h) const {
  if (!std::isfinite(layer_depth) || h <= 0) return 0;
  return -std::expm1(-h / layer_depth);
}

double BedFriction::active_depth(double h) const {
  if (h <= 0) return 0;
  if (!std::isfinite(layer_depth)) return h;
  return -layer_depth * std::expm1(-h / layer_depth);
}

double BedFriction::mu(double h, double a, double speed, double g_normal) const {
  const double ms = mu_static(h);
  if (delta_mu <= 0 || speed <= 0 || a <= 0 || g_normal <= 0) return ms;
  const double inertial = speed * grain_diameter / (a * std::sqrt(g_normal * a));
  return ms + delta_mu * inertial / (i0 + inertial);
}

BedFriction bed_friction_from_yaml(YamlMap m) {
  BedFriction f;
  f.internal_deg = m.number_or("internal_friction_deg", f.internal_deg, Range{0, 89, true, false});
  f.basal_deg = m.number_or("basal_friction_deg", f.basal_deg, Range{0, 89, true, false});
  f.delta_mu = m.number_or("delta_mu", f.delta_mu, Range::closed(0, 10));
  f.start_excess_deg = m.number_or("start_excess_deg", f.start_excess_deg, Range::closed(0, 30));
  if (f.internal_deg + f.start_excess_deg >= 89) {
    throw InputError(m.where("start_excess_deg") + ": internal_friction_deg + start_excess_deg must stay below 89 deg (got " +
                     std::to_string(f.internal_deg + f.start_excess_deg) + ")");
  }
  f.i0 = m.number_or("i0", f.i0, Range{0, 100, true, false});
  f.grain_diameter = m.number_or("grain_diameter", f.grain_diameter, Range{0, 1, true, false});
  if (m.has("flowing_layer_depth") && m.has("flowing_layer_diameters")) {
    throw InputError(m.where("flowing_layer_depth") + ": give flowing_layer_depth or flowing_layer_diameters, not both");
  }
  const bool plug = m.boolean_or("plug", false);
  if (plug && (m.has("flowing_layer_depth") || m.has("flowing_layer_diameters"))) {
    throw InputError(m.where("plug") + ": a plug (the whole depth moves, classical Savage-Hutter) has no flowing layer; "
                     "drop flowing_layer_depth / flowing_layer_diameters or plug");
  }
  if (plug) {
    f.layer_depth = std::numeric_limits<double>::infinity();
  } else if (m.has("flowing_layer_depth")) {
    f.layer_depth = m.number("flowing_layer_depth", Range{0, 1e3, true, false});
  } else {
    f.layer_depth = f.grain_diameter * m.number_or("flowing_layer_diameters", 10, Range{0, 1e6, true, false});
  }
  f.side_walls.friction = m.number_or("wall_friction", std::tan(f.basal_deg * kDeg), Range::closed(0, 2));
  f.savage_hutter_pressure = m.choice_or("earth_pressure", "hydrostatic", {"hydrostatic", "savage_hutter"}) == "savage_hutter";
  m.finish();
  return f;
}

}  // namespace grainscale::continuum::closure
