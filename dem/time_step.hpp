#pragma once
// Time-step estimates for Hertzian contacts.
//
// Rayleigh time (Li, Xu & Thornton 2005; the critical step used by EDEM): the time a Rayleigh surface
// wave takes to cross a sphere,  T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766).
// EDEM recommends 20-40 % of T_R for dense systems; grainscale's default is 20 %.
//
// Hertz contact duration (Johnson 1985, eq. 11.47): for impact speed v,
//   t_c = 2.868 (m*^2 / (R* E*^2 v))^(1/5),   delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5).
#include <cmath>
#include <numbers>

#include "dem/material.hpp"

namespace grainscale::dem {

inline double rayleigh_time(double radius, const Material& m) {
  return std::numbers::pi * radius * std::sqrt(m.density / m.shear_modulus) / (0.1631 * m.poisson_ratio + 0.8766);
}

inline double hertz_contact_time(double r_eff, double m_eff, double e_eff, double v) {
  return 2.868 * std::pow(m_eff * m_eff / (r_eff * e_eff * e_eff * v), 0.2);
}

inline double hertz_max_overlap(double r_eff, double m_eff, double e_eff, double v) {
  return std::pow(15.0 * m_eff * v * v / (16.0 * e_eff * std::sqrt(r_eff)), 0.4);
}

}  // namespace grainscale::dem
