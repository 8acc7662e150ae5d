#pragma once
// Is the time step stable for the contact network as it is now? A per-body check that catches what
// the single-contact criterion (ForceDiagnostics::max_omega_dt) misses: a light body squeezed
// through several contacts at once, e.g. a chaff flake trapped between a landing grain and the
// floor, whose fastest mode is much faster than any one contact's.
//
// The leapfrog (velocity Verlet) step, with damping evaluated from half-step velocities as here, is
// stable for a damped oscillator of frequency Omega and damping ratio zeta only while (Belytschko,
// Liu & Moran, "Nonlinear Finite Elements for Continua and Structures", 2000, Sec. 6.2.6)
//
//   Omega dt <= 2 (sqrt(1 + zeta^2) - zeta),
//
// so damping (low restitution) lowers the limit. The margin reported is, for the worst body,
// Omega dt / [2 (sqrt(1 + zeta^2) - zeta)]: above 1 the step amplifies that body's motion.
//
// Each body's fastest mode is found in two stages:
//  1. A cheap bound for every body (Gershgorin's theorem on M^-1/2 K M^-1/2, each contact a spring
//     between two contact points):
//        Omega_b^2 <= sum_c S_n,c (a_b,c + sqrt(a_b,c a_o,c)),
//     a_b,c = 1/m_b + (r x n)^T I_b^-1 (r x n) the compliance of body b at the contact point (the
//     inverse effective mass of an off-centre push), a_o,c the other body's (0 for a wall); damping
//     likewise with c_n,c. Exact for two equal spheres; conservative for clumps (about 2x).
//  2. For bodies whose bound exceeds kRefineAbove: the body's own 6-degree-of-freedom problem
//     K phi = Omega^2 M phi with K = sum_c k_c J_c^T J_c, J_c = [n^T, (r x n)^T],
//     k_c = S_n,c (1 + sqrt(a_o,c / a_b,c)) (the partner's mobility, exact for two equal bodies,
//     nothing for a wall or a far heavier partner), M = diag(m, m, m, I_world); zeta of the top
//     mode phi (M-normalised) is phi^T C phi / (2 Omega), C built like K from the damping.
// S_n = 2 E* sqrt(R* delta) and c_n = 2 sqrt(5/6) |beta| sqrt(S_n m*) as in HertzMindlin.
//
// Run every few steps rather than every step; no allocation once the buffers have grown.
#include <cstdint>
#include <string>
#include <vector>

#include "dem/bodies.hpp"
#include "dem/force_field.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/particles.hpp"
#include "dem/wall.hpp"

namespace grainscale::dem {

struct StepStability {
  double margin = 0;       // worst body's Omega dt / [2 (sqrt(1 + zeta^2) - zeta)]; > 1: unstable
  double omega_dt = 0;     // Omega_b dt of that body
  double zeta = 0;         // its damping ratio
  std::int64_t body = -1;  // its index in Bodies, -1 if no contacts
  int contacts = 0;        // how many contacts it had
  bool refined = false;    // from the body's own 6-dof mode (stage 2) rather than the bound
};

class StepStabilityMonitor {
 public:
  /// Bodies whose stage-1 bound exceeds this get the stage-2 local mode.
  static constexpr double kRefineAbove = 0.5;

  StepStability assess(const Particles& p, const Bodies& b, const NeighborList& nl, const std::vector<Wall>& walls,
                       const ForceField& forces, double dt);
  /// Per body, the last assess()'s stage-1 bound on Omega^2 (0 for a body without contacts).
  const std::vector<double>& omega2_bounds() const { return omega2_; }
  /// Per body, the last assess()'s margin: the 6-dof mode's for the bodies refined in stage 2, for
  /// the other suspects the bound that ruled them out (their 6 x 6 Gershgorin bound, or the stage-1
  /// bound for those not reached), the stage-1 bound's for the rest, 0 for a body without contacts.
  const std::vector<double>& margins() const { return margin_; }
  /// How many suspects the last assess() solved the 6-dof eigenproblem of.
  std::size_t refined() const { return refined_; }
  /// The reference stage 2, which the tests compare the fast one with (the same worst body, bit for
  /// bit): solve every suspect's eigenproblem, not only those whose bound could be the worst
  /// (`every_suspect`); find each suspect's contacts by walking every contact, as for bodies not yet
  /// indexed, not from its spheres' rows and reverse ranges (`every_contact`).
  void use_reference_stage2(bool every_suspect, bool every_contact) {
    refine_every_suspect_ = every_suspect;
    refine_from_every_contact_ = every_contact;
  }

 private:
  struct Spring {  // one contact as seen by one body
    Vec3 n, r;     // normal and lever (contact point - centre of mass)
    double stiffness, damping;
  };
  template <class Visit>
  void for_each_contact(const Particles& p, const Bodies& b, const NeighborList& nl, const std::vector<Wall>& walls,
                        const ForceField& forces, Visit&& visit) const;
  template <class Visit>
  void for_each_pair_contact(const Particles& p, const Bodies& b, const NeighborList& nl, const ForceField& forces,
                             std::size_t k0, std::size_t k1, Visit&& visit) const;
  template <class Visit>
  void for_each_wall_contact(const Particles& p, const Bodies& b, const std::vector<Wall>& walls,
                             const ForceField& forces, const std::uint32_t* near, std::size_t i0, std::size_t i1,
                             Visit&& visit) const;

  /// A body's compliance at a contact without turning the lever into the body frame each time:
  /// 1/m + c^T I_world^-1 c for c = r x n, with I_world^-1 = R diag(1/I) R^T made once per check.
  struct Mobility {
    double inv_mass, xx, yy, zz, xy, xz, yz;  // 1/m and the symmetric I_world^-1
    double compliance(const Vec3& r, const Vec3& n) const {
      const Vec3 c = cross(r, n);
      return inv_mass + (xx * c.x * c.x + yy * c.y * c.y + zz * c.z * c.z) +
             2 * (xy * c.x * c.y + xz * c.x * c.z + yz * c.y * c.z);
    }
  };

  std::vector<Mobility> mobility_;                       // per body, made at each check
  std::vector<double> omega2_, damping_rate_, margin_;  // per body, reused between calls
  std::vector<int> count_, suspect_;                    // suspect_[b]: index into springs_ or -1
  std::vector<std::vector<Spring>> springs_;            // per suspect (found by body: [0], one at a time)
  std::vector<std::uint32_t> entries_;                  // a suspect's neighbour-list entries, in order
  std::vector<std::uint32_t> order_;                    // the suspects, worst stage-1 bound first
  bool refine_from_every_contact_ = false, refine_every_suspect_ = false;
  std::size_t refined_ = 0;
  struct PairTerms {  // one contact's stage-1 terms for its two bodies (i: the owner's, j: the partner's)
    double stiffness_i, damping_i, stiffness_j, damping_j;
    std::uint32_t body_i, body_j;
  };
  std::vector<PairTerms> pair_terms_;  // per neighbour-list entry; stiffness_i -1 for a pair apart
  struct Term {  // one wall contact's stage-1 terms
    std::uint32_t body;
    double stiffness, damping;
  };
  std::vector<std::vector<Term>> wall_terms_;  // per thread, in sphere order
};

/// "margin 1.3 at body id 17 (4 spheres, 8 contacts, ...): Omega dt = 0.9, damping ratio 1.5" for
/// logs and error messages.
std::string describe(const StepStability& s, const Bodies& b);

}  // namespace grainscale::dem
