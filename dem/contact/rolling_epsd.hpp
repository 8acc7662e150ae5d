#pragma once
// Elastic-plastic spring-dashpot (EPSD) rolling resistance, Ai, Chen, Rotter & Ooi (2011), Powder
// Technology 206:269, model type C (EDEM "Type C", LIGGGHTS "epsd2"):
//
//   relative rolling    omega_r = (omega_i - omega_j) projected on the tangent plane
//   spring (eq. 13)     M_k += -k_r omega_r dt,   |M_k| <= M_m = mu_r R_r F_n+   (full mobilisation)
//   stiffness (eq. 15)  k_r = k_stiff * k_n * mu_r^2 * R_r^2,   k_stiff = 2.25 (Ai et al.), R_r = R*
//   damper (eq. 16-18)  M_d = -C_r omega_r while |M_k| < M_m, 0 once fully mobilised (f = 0),
//                       C_r = 2 eta_r sqrt(I_r k_r),  1/I_r = 1/(I_i + m_i r_i^2) + 1/(I_j + m_j r_j^2)
//
// torque_i = M_k + M_d, torque_j = -(M_k + M_d). The spring torque is kept in the contact history
// and turned with the contact frame like the Mindlin tangential displacement. k_n is the current
// Hertz normal stiffness S_n.
#include <cmath>

#include "dem/contact/contact_kinematics.hpp"
#include "dem/material.hpp"

namespace grainscale::dem {

struct EpsdRolling {
  /// The spring torque M_k lives in ContactHistory::rolling.
  static constexpr bool kSpring = true;
  struct Params {
    double mu_r = 0;
    double stiffness_factor = 2.25;  // k_stiff in eq. 15
    double damping_ratio = 0.3;      // eta_r
  };
  static Params make(const PairProperties& p, double stiffness_factor, double damping_ratio) {
    return {p.rolling_friction, stiffness_factor, damping_ratio};
  }

  static void evaluate(const Params& p, const ContactKinematics& c, const ContactForce& f, ContactHistory& h,
                       Vec3& torque_i, Vec3& torque_j) {
    const Vec3 w = c.omega_i - c.omega_j;
    const Vec3 w_r = w - dot(w, c.n) * c.n;
    const double k_r = p.stiffness_factor * f.stiffness * p.mu_r * p.mu_r * c.r_eff * c.r_eff;
    const double m_max = p.mu_r * c.r_eff * std::max(f.normal, 0.0);

    project_to_tangent_plane(h.rolling, c.n);
    h.rolling += (-k_r * c.dt) * w_r;
    const double m_k = norm(h.rolling);
    Vec3 total;
    if (m_k >= m_max) {
      if (m_k > 0) h.rolling *= m_max / m_k;
      total = h.rolling;
    } else {
      const double inv_ir = 1.0 / (c.inertia_i + c.mass_i * c.lever_i * c.lever_i) +
                            (std::isfinite(c.inertia_j) ? 1.0 / (c.inertia_j + c.mass_j * c.lever_j * c.lever_j) : 0.0);
      const double c_r = 2.0 * p.damping_ratio * std::sqrt(k_r / inv_ir);
      total = h.rolling - c_r * w_r;
    }
    torque_i = total;
    torque_j = -total;
  }
};

}  // namespace grainscale::dem
