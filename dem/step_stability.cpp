#include "dem/step_stability.hpp"
#include "dem/parallel.hpp"
#include "dem/work_split.hpp"

#include <omp.h>

#include "dem/eigen_dense.hpp"
#include <algorithm>
#include <cmath>
#include <sstream>


namespace grainscale::dem {

namespace {

/// R (principal frame -> world) of orientation q.
Eigen::Matrix3d rotation_matrix(const Quat& q) { return Eigen::Quaterniond(q.w, q.x, q.y, q.z).toRotationMatrix(); }

double margin_of(double omega_dt, double zeta) { return omega_dt / (2 * (std::sqrt(1 + zeta * zeta) - zeta)); }

}  // namespace

/// Calls visit(entry, body, lever, normal, other_body, other_lever, S_n, c_n) for the contacts of
/// neighbour-list entries [k0, k1), once per pair (the visitor handles both sides), in entry order.
/// The pairs are walked by entry, not by sphere (most spheres of a settled bed own no entry: a loop
/// per sphere paid a mispredicted branch for each, as the force loop did).
template <class Visit>
void StepStabilityMonitor::for_each_pair_contact(const Particles& p, const Bodies& b, const NeighborList& nl,
                                                 const ForceField& forces, std::size_t k0, std::size_t k1,
                                                 Visit&& visit) const {
  for (std::size_t k = k0; k < k1; ++k) {
    const std::uint32_t i = nl.owner(static_cast<std::uint32_t>(k)), j = nl.partner(static_cast<std::uint32_t>(k));
    const Vec3 d = p.x[i] - p.x[j];
    const double rsum = p.radius[i] + p.radius[j];
    const double dist2 = norm2(d);
    if (dist2 >= rsum * rsum) continue;
    const double dist = std::sqrt(dist2);
    const std::uint32_t bi = p.body[i];
    const Vec3 n = (1.0 / dist) * d;
    const double overlap = rsum - dist;
    const Vec3 point = p.x[i] - (p.radius[i] - 0.5 * overlap) * n;
    const std::uint32_t bj = p.body[j];
    const HertzMindlin::Params& hm = forces.contact_params(p.material[i], p.material[j]);
    const double r_eff = p.radius[i] * p.radius[j] / rsum;
    const double m_eff = b.mass[bi] * b.mass[bj] / (b.mass[bi] + b.mass[bj]);
    const double s_n = 2.0 * hm.e_eff * std::sqrt(r_eff * overlap);
    visit(k, bi, point - b.x[bi], n, static_cast<std::int64_t>(bj), point - b.x[bj], s_n,
          hm.damping * std::sqrt(s_n * m_eff));
  }
}

/// The same for the wall contacts of spheres [i0, i1), sphere by sphere, the sphere in place of the
/// entry (other_body -1, other_lever zero). Walls out of a sphere's reach are skipped as the force
/// loop skips them (asking every wall of every sphere was a third of this loop on the clump bed;
/// BoxGeometry::nearby in the profile).
template <class Visit>
void StepStabilityMonitor::for_each_wall_contact(const Particles& p, const Bodies& b, const std::vector<Wall>& walls,
                                                 const ForceField& forces, const std::uint32_t* near,
                                                 std::size_t i0, std::size_t i1, Visit&& visit) const {
  for (std::size_t i = i0; i < i1; ++i) {
    if (ForceField::all_out_of_reach(near, i, walls.size())) continue;
    const std::uint32_t bi = p.body[i];
    for (std::size_t wi = 0; wi < walls.size(); ++wi) {
      if (ForceField::out_of_reach(near, i, wi)) continue;
      const Wall& w = walls[wi];
      WallContact wc[ForceField::kWallSlots];
      const int found = w.contacts(p.x[i], p.radius[i], wc, ForceField::kWallSlots);
      for (int q = 0; q < found; ++q) {
        const HertzMindlin::Params& hm = forces.contact_params(p.material[i], w.material());
        const double s_n = 2.0 * hm.e_eff * std::sqrt(p.radius[i] * wc[q].overlap);
        const Vec3 point = p.x[i] - (p.radius[i] - wc[q].overlap) * wc[q].normal;
        visit(i, bi, point - b.x[bi], wc[q].normal, std::int64_t{-1}, Vec3{}, s_n,
              hm.damping * std::sqrt(s_n * b.mass[bi]));
      }
    }
  }
}

/// Every contact: the pairs in entry order, then the wall contacts sphere by sphere.
template <class Visit>
void StepStabilityMonitor::for_each_contact(const Particles& p, const Bodies& b, const NeighborList& nl,
                                            const std::vector<Wall>& walls, const ForceField& forces,
                                            Visit&& visit) const {
  auto contact_only = [&](std::size_t, auto&&... contact) { visit(contact...); };
  for_each_pair_contact(p, b, nl, forces, 0, nl.entries(), contact_only);
  for_each_wall_contact(p, b, walls, forces, forces.near_wall_masks(walls, nl, p.size()), 0, p.size(), contact_only);
}

StepStability StepStabilityMonitor::assess(const Particles& p, const Bodies& b, const NeighborList& nl,
                                           const std::vector<Wall>& walls, const ForceField& forces, double dt) {
  const std::size_t nb = b.size(), n = p.size(), entries = nl.entries();
  mobility_.resize(nb);
  omega2_.assign(nb, 0.0);
  damping_rate_.assign(nb, 0.0);
  count_.assign(nb, 0);
  margin_.resize(nb);
  const std::uint32_t* const near = forces.near_wall_masks(walls, nl, n);

  // 1/m + (r x n)^T I_world^-1 (r x n) is body k's inverse effective mass for a push along n at
  // x + r. I_world^-1 = R diag(1/I) R^T is made once per body here, not by turning every lever into
  // the body frame (three divisions per contact side: a quarter of the check on the clump bed).
  auto make_mobility = [&](std::size_t k) {
    const Eigen::Matrix3d R = rotation_matrix(b.q[k]);
    const Eigen::Vector3d inv_I(1 / b.inertia[k].x, 1 / b.inertia[k].y, 1 / b.inertia[k].z);
    const Eigen::Matrix3d w = R * inv_I.asDiagonal() * R.transpose();
    mobility_[k] = {b.inv_mass[k], w(0, 0), w(1, 1), w(2, 2), w(0, 1), w(0, 2), w(1, 2)};
  };
  // A contact's terms for its bodies: S_n (a + sqrt(a_b a_o)) and c_n likewise (a_o = 0 for a wall).
  auto terms = [&](std::size_t bi, const Vec3& ri, const Vec3& normal, std::int64_t bj, const Vec3& rj, double s_n,
                   double c_n) {
    const double ai = mobility_[bi].compliance(ri, normal);
    const double aj = bj >= 0 ? mobility_[static_cast<std::size_t>(bj)].compliance(rj, normal) : 0.0;
    const double cross_term = std::sqrt(ai * aj);
    return PairTerms{s_n * (ai + cross_term), c_n * (ai + cross_term), s_n * (aj + cross_term),
                     c_n * (aj + cross_term), static_cast<std::uint32_t>(bi), static_cast<std::uint32_t>(bj)};
  };
  auto add = [&](std::uint32_t body, double stiffness, double damping) {
    omega2_[body] += stiffness;
    damping_rate_[body] += damping;
    ++count_[body];
  };
  auto make_margin = [&](std::size_t k) {
    margin_[k] = count_[k] > 0 ? margin_of(std::sqrt(omega2_[k]) * dt, damping_rate_[k] / (2 * std::sqrt(omega2_[k])))
                               : 0;
  };

  // Stage 1: Gershgorin row sums, each body's added in one fixed order for any thread count (the
  // pairs in entry order, then the wall contacts sphere by sphere), so the same sums bit for bit.
  // One thread adds each contact's terms as found. A team makes them in parallel (threads take
  // contiguous ranges of entries and of spheres), the pairs' stored by entry and the walls' listed
  // per thread in sphere order; then each thread walks them all, in that order, and adds those of
  // its own bodies. (Until 2026-12-05 one thread added them all: the clump bed's check took as long
  // on two threads as on one. Summed per sphere and then per body, an order of its own, it cost a
  // fifth more on one thread. docs/performance.md, "fifth session".)
  const int team = entries + n >= parallel_min_items() ? omp_get_max_threads() : 1;
  if (team == 1) {
    for (std::size_t k = 0; k < nb; ++k) make_mobility(k);
    for_each_contact(p, b, nl, walls, forces,
                     [&](std::size_t bi, const Vec3& ri, const Vec3& normal, std::int64_t bj, const Vec3& rj,
                         double s_n, double c_n) {
                       const PairTerms pt = terms(bi, ri, normal, bj, rj, s_n, c_n);
                       add(pt.body_i, pt.stiffness_i, pt.damping_i);
                       if (bj >= 0) add(pt.body_j, pt.stiffness_j, pt.damping_j);
                     });
    for (std::size_t k = 0; k < nb; ++k) make_margin(k);
  } else {
    pair_terms_.resize(entries);
    if (wall_terms_.size() < static_cast<std::size_t>(team)) wall_terms_.resize(static_cast<std::size_t>(team));
#pragma omp parallel num_threads(team)
    {
      const int threads = omp_get_num_threads(), t = omp_get_thread_num();
      std::size_t first = 0, last = 0;
      equal_share(nb, threads, t, first, last);
      for (std::size_t k = first; k < last; ++k) make_mobility(k);
#pragma omp barrier
      std::size_t lo = 0, hi = 0;
      equal_share(entries, threads, t, lo, hi);
      for (std::size_t k = lo; k < hi; ++k) pair_terms_[k].stiffness_i = -1;  // apart until found touching
      for_each_pair_contact(p, b, nl, forces, lo, hi,
                            [&](std::size_t k, std::size_t bi, const Vec3& ri, const Vec3& normal, std::int64_t bj,
                                const Vec3& rj, double s_n, double c_n) {
                              pair_terms_[k] = terms(bi, ri, normal, bj, rj, s_n, c_n);
                            });
      std::vector<Term>& mine = wall_terms_[static_cast<std::size_t>(t)];
      mine.clear();
      equal_share(n, threads, t, lo, hi);
      for_each_wall_contact(p, b, walls, forces, near, lo, hi,
                            [&](std::size_t, std::size_t bi, const Vec3& ri, const Vec3& normal, std::int64_t bj,
                                const Vec3& rj, double s_n, double c_n) {
                              const PairTerms pt = terms(bi, ri, normal, bj, rj, s_n, c_n);
                              mine.push_back({pt.body_i, pt.stiffness_i, pt.damping_i});
                            });
#pragma omp barrier
      const auto mine_first = static_cast<std::uint32_t>(first), mine_last = static_cast<std::uint32_t>(last);
      auto is_mine = [&](std::uint32_t body) { return body >= mine_first && body < mine_last; };
      for (std::size_t k = 0; k < entries; ++k) {
        const PairTerms& pt = pair_terms_[k];
        if (pt.stiffness_i < 0) continue;
        if (is_mine(pt.body_i)) add(pt.body_i, pt.stiffness_i, pt.damping_i);
        if (is_mine(pt.body_j)) add(pt.body_j, pt.stiffness_j, pt.damping_j);
      }
      for (int u = 0; u < threads; ++u) {
        for (const Term& term : wall_terms_[static_cast<std::size_t>(u)]) {
          if (is_mine(term.body)) add(term.body, term.stiffness, term.damping);
        }
      }
      for (std::size_t k = first; k < last; ++k) make_margin(k);
    }
  }

  // The worst body by its bound, and the suspects (numbered in body order) for stage 2.
  StepStability worst;
  std::size_t suspects = 0;
  refined_ = 0;
  suspect_.assign(nb, -1);
  for (std::size_t k = 0; k < nb; ++k) {
    if (count_[k] == 0) continue;
    if (margin_[k] > kRefineAbove) {
      suspect_[k] = static_cast<int>(suspects++);
    } else if (margin_[k] > worst.margin) {
      const double omega = std::sqrt(omega2_[k]);
      worst = {margin_[k], omega * dt, damping_rate_[k] / (2 * omega), static_cast<std::int64_t>(k), count_[k], false};
    }
  }
  if (suspects == 0) return worst;

  // Stage 2: the suspects' own 6-dof modes.
  //
  // Which suspects: the margin is monotone in the mode's frequency Omega and in its damping
  // c = phi^T C phi = 2 zeta Omega, since Omega dt / [2 (sqrt(1 + zeta^2) - zeta)] =
  // (dt / 2) (sqrt(Omega^2 + c^2 / 4) + c / 2). Two bounds on Omega^2 and c give bounds on it:
  //  - the traces, Omega^2 <= tr K' = sum_c k_c |J_c|^2 = sum_c S_n (a_b + sqrt(a_b a_o)) with J_c
  //    mass-normalised (|J_c|^2 = a_b), which is stage 1's sum, and c <= tr C' likewise: a suspect's
  //    stage-1 margin bounds its stage-2 margin. Taken in order of it, the first suspect whose
  //    stage-1 margin is below the worst margin found so far ends the search, before its contacts
  //    are even gathered;
  //  - Gershgorin's theorem on the body's 6 x 6 K' and C' (their largest absolute row sums), once its
  //    contacts are gathered: below the worst so far, its eigenproblem is skipped.
  // The worst body is the same as solving every suspect's (ties to the lower body). On the tilting
  // platform box, of ~1,660 suspects among 14,521 bodies ~1,250 were gathered and 20 solved
  // (docs/performance.md, "eleventh session").
  //
  // Each suspect's contacts: the pairs in entry order, then the wall contacts sphere by sphere, the
  // order of the walk over every contact in stage 1, so the same matrices bit for bit whichever way
  // they are found. With the bodies indexed by sphere and the list covering every sphere, they are
  // found from the suspect's spheres' rows and reverse ranges (walking every contact again cost as
  // much as stage 1); else by walking every contact once more.
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  // Whether body k's bound (margin_[k]) rules it out: below the worst margin found so far.
  // (1e-6: room for the round-off of margin_of and of the eigenvalue, far above either.)
  auto beyond_worst = [&](std::size_t k) { return !refine_every_suspect_ && margin_[k] * (1 + 1e-6) < worst.margin; };
  auto refine = [&](std::size_t k, const std::vector<Spring>& springs) {
    // Work in mass-normalised coordinates: K' = M^-1/2 K M^-1/2.
    const Eigen::Matrix3d R = rotation_matrix(b.q[k]);
    const Eigen::Vector3d inv_sqrt_I(1 / std::sqrt(b.inertia[k].x), 1 / std::sqrt(b.inertia[k].y),
                                     1 / std::sqrt(b.inertia[k].z));
    const Eigen::Matrix3d rot_scale = R * inv_sqrt_I.asDiagonal() * R.transpose();  // I_world^-1/2
    const double lin_scale = 1 / std::sqrt(b.mass[k]);
    Mat6 K = Mat6::Zero(), C = Mat6::Zero();
    for (const Spring& s : springs) {
      const Vec3 rn = cross(s.r, s.n);
      Vec6 j;
      j.head<3>() = lin_scale * Eigen::Vector3d(s.n.x, s.n.y, s.n.z);
      j.tail<3>() = rot_scale * Eigen::Vector3d(rn.x, rn.y, rn.z);
      K += s.stiffness * j * j.transpose();
      C += s.damping * j * j.transpose();
    }
    const double g_k = K.cwiseAbs().rowwise().sum().maxCoeff(), g_c = C.cwiseAbs().rowwise().sum().maxCoeff();
    margin_[k] = 0.5 * dt * (std::sqrt(g_k + 0.25 * g_c * g_c) + 0.5 * g_c);
    if (beyond_worst(k)) return;
    const Eigen::SelfAdjointEigenSolver<Mat6> eig(K);
    const double omega = std::sqrt(std::max(eig.eigenvalues()(5), 0.0));
    const Vec6 phi = eig.eigenvectors().col(5);
    const double zeta = omega > 0 ? phi.dot(C * phi) / (2 * omega) : 0;
    const double margin = margin_of(omega * dt, zeta);
    margin_[k] = margin;
    ++refined_;
    const auto body = static_cast<std::int64_t>(k);
    if (margin > worst.margin || (margin == worst.margin && worst.refined && body < worst.body))
      worst = {margin, omega * dt, zeta, body, count_[k], true};
  };
  // A spring of contact (bi, bj) for body `side` (one of them), the partner's mobility in its stiffness.
  auto spring_for = [&](std::size_t side, std::size_t bi, const Vec3& ri, const Vec3& n, std::int64_t bj,
                        const Vec3& rj, double s_n, double c_n) {
    const double ai = mobility_[bi].compliance(ri, n);
    const double aj = bj >= 0 ? mobility_[static_cast<std::size_t>(bj)].compliance(rj, n) : 0.0;
    const double f = side == bi ? 1 + std::sqrt(aj / ai) : 1 + std::sqrt(ai / aj);
    return side == bi ? Spring{n, ri, f * s_n, f * c_n} : Spring{n, rj, f * s_n, f * c_n};
  };

  order_.clear();
  for (std::size_t k = 0; k < nb; ++k)
    if (suspect_[k] >= 0) order_.push_back(static_cast<std::uint32_t>(k));
  if (!refine_every_suspect_) {
    std::stable_sort(order_.begin(), order_.end(), [&](std::uint32_t x, std::uint32_t y) { return margin_[x] > margin_[y]; });
  }
  const bool by_body = !refine_from_every_contact_ && b.indexed(n) && nl.starts().size() == n + 1 &&
                       nl.rev_starts().size() == n + 1;
  if (by_body) {
    if (springs_.empty()) springs_.resize(1);
    std::vector<Spring>& springs = springs_[0];
    for (const std::uint32_t k : order_) {
      if (beyond_worst(k)) break;
      springs.clear();
      entries_.clear();
      for (std::uint32_t m = b.sphere_start[k]; m < b.sphere_start[k + 1]; ++m) {
        const std::uint32_t s = b.sphere_slot[m];
        for (std::uint32_t e = nl.begin(s); e < nl.end(s); ++e) entries_.push_back(e);
        for (std::uint32_t r = nl.rev_begin(s); r < nl.rev_end(s); ++r) entries_.push_back(nl.rev_entry(r));
      }
      std::sort(entries_.begin(), entries_.end());  // entry order, as the whole walk meets them
      auto add_spring = [&](std::size_t, std::size_t bi, const Vec3& ri, const Vec3& normal, std::int64_t bj,
                            const Vec3& rj, double s_n, double c_n) {
        springs.push_back(spring_for(k, bi, ri, normal, bj, rj, s_n, c_n));
      };
      for (const std::uint32_t e : entries_) for_each_pair_contact(p, b, nl, forces, e, e + 1, add_spring);
      for (std::uint32_t m = b.sphere_start[k]; m < b.sphere_start[k + 1]; ++m) {  // slots ascending
        const std::uint32_t s = b.sphere_slot[m];
        for_each_wall_contact(p, b, walls, forces, near, s, s + 1, add_spring);
      }
      refine(k, springs);
    }
    return worst;
  }
  if (springs_.size() < suspects) springs_.resize(suspects);
  for (std::size_t s = 0; s < suspects; ++s) springs_[s].clear();
  for_each_contact(p, b, nl, walls, forces,
                   [&](std::size_t bi, const Vec3& ri, const Vec3& normal, std::int64_t bj, const Vec3& rj,
                       double s_n, double c_n) {
                     if (suspect_[bi] >= 0)
                       springs_[static_cast<std::size_t>(suspect_[bi])].push_back(
                           spring_for(bi, bi, ri, normal, bj, rj, s_n, c_n));
                     if (bj >= 0 && suspect_[static_cast<std::size_t>(bj)] >= 0)
                       springs_[static_cast<std::size_t>(suspect_[static_cast<std::size_t>(bj)])].push_back(
                           spring_for(static_cast<std::size_t>(bj), bi, ri, normal, bj, rj, s_n, c_n));
                   });
  for (const std::uint32_t k : order_) {
    if (beyond_worst(k)) break;
    refine(k, springs_[static_cast<std::size_t>(suspect_[k])]);
  }
  return worst;
}

std::string describe(const StepStability& s, const Bodies& b) {
  std::ostringstream o;
  o << "step stability margin " << s.margin;
  if (s.body >= 0) {
    const auto k = static_cast<std::size_t>(s.body);
    o << " at body id " << b.id[k] << " (" << b.sphere_start[k + 1] - b.sphere_start[k] << " spheres, mass " << b.mass[k]
      << " kg, " << s.contacts << " contacts, at (" << b.x[k].x << ", " << b.x[k].y << ", " << b.x[k].z
      << ") m): Omega dt = " << s.omega_dt << ", damping ratio " << s.zeta << (s.refined ? "" : " (bound)")
      << "; stable below 1";
  }
  return o.str();
}

}  // namespace grainscale::dem
