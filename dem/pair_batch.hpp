#pragma once
// A batch of touching sphere pairs, evaluated together so that the compiler vectorises the contact
// models (dem/force_field.cpp, pass 1).
//
// Why: in a settled bed most neighbour entries are apart (2.7 entries, 0.43 contacts per sphere in
// the clump bed), and a contact costs seven square roots and several divisions, whose latency one
// contact at a time cannot hide. The pair loop therefore only finds the contacts and copies what the
// models need into these arrays (one array per quantity, so a vector register loads 8 contacts at
// once); `evaluate` runs the models over the whole batch in one `omp simd` loop; the caller then sums
// the owners' shares and stores the partners'.
//
// Same numbers, bit for bit: every contact is computed by the same expressions in the same order as
// one at a time (the models are branch-free; IEEE square root and division are exact in vector form
// too; no FMA: -ffp-contract=off), and nothing is summed across contacts here. The owner's sum is
// still taken in entry order by the caller.
#include <algorithm>
#include <cstdint>

#include "dem/contact/contact_kinematics.hpp"
#include "dem/contact/hertz_mindlin.hpp"

namespace grainscale::dem {

template <class Rolling>
struct PairBatch {
  static constexpr int kCapacity = 64;
  int size = 0;

  // In: the pair's geometry and the two spheres' state (i the owner, j the partner).
  alignas(64) double dx[kCapacity], dy[kCapacity], dz[kCapacity];  // x_i - x_j
  alignas(64) double dist2[kCapacity], rsum[kCapacity], ri[kCapacity], rj[kCapacity];
  alignas(64) double dvx[kCapacity], dvy[kCapacity], dvz[kCapacity];  // v_i - v_j
  alignas(64) double wix[kCapacity], wiy[kCapacity], wiz[kCapacity];
  alignas(64) double wjx[kCapacity], wjy[kCapacity], wjz[kCapacity];
  alignas(64) double mi[kCapacity], mj[kCapacity], ii[kCapacity], ij[kCapacity];
  HertzMindlin::Params contact[kCapacity];
  typename Rolling::Params rolling[kCapacity];
  // In and out: the contact's history (ContactHistory, one array per component; the rolling spring
  // r* only for models with one, Rolling::kSpring: for the others it is neither filled nor read).
  alignas(64) double sx[kCapacity], sy[kCapacity], sz[kCapacity], rx[kCapacity], ry[kCapacity], rz[kCapacity];
  // Where it goes: owner slot, neighbour entry (the history's and the partner share's place).
  std::uint32_t owner[kCapacity], entry[kCapacity];
  // Out: force on i, i's torque share (its rolling torque plus lever x tangential force), j's.
  alignas(64) double fx[kCapacity], fy[kCapacity], fz[kCapacity];
  alignas(64) double tix[kCapacity], tiy[kCapacity], tiz[kCapacity];
  alignas(64) double tjx[kCapacity], tjy[kCapacity], tjz[kCapacity];

  // Out, for the monitors: overlap / smaller radius, normal stiffness / m*.
  alignas(64) double overlap_ratio[kCapacity], stiffness_per_mass[kCapacity];

  /// Runs the contact and rolling models over the batch.
  void evaluate(double dt) {
    // (No `omp simd`: its per-lane copies of the structs below stop GCC vectorising; the structs
    // are taken apart into registers once the models are inlined.)
#pragma GCC ivdep
    for (int b = 0; b < size; ++b) {
      // As the one-at-a-time loop did (docs: dem/contact/contact_kinematics.hpp).
      const double dist = std::sqrt(dist2[b]);
      ContactKinematics c;
      c.n = (1.0 / dist) * Vec3{dx[b], dy[b], dz[b]};
      c.overlap = rsum[b] - dist;
      c.lever_i = ri[b] - 0.5 * c.overlap;
      c.lever_j = rj[b] - 0.5 * c.overlap;
      c.omega_i = {wix[b], wiy[b], wiz[b]};
      c.omega_j = {wjx[b], wjy[b], wjz[b]};
      c.v_rel = Vec3{dvx[b], dvy[b], dvz[b]} - cross(c.lever_i * c.omega_i + c.lever_j * c.omega_j, c.n);
      c.r_eff = ri[b] * rj[b] / rsum[b];
      c.mass_i = mi[b];
      c.mass_j = mj[b];
      c.m_eff = c.mass_i * c.mass_j / (c.mass_i + c.mass_j);
      c.inertia_i = ii[b];
      c.inertia_j = ij[b];
      c.dt = dt;
      ContactHistory h{{sx[b], sy[b], sz[b]}, {}};
      if constexpr (Rolling::kSpring) h.rolling = {rx[b], ry[b], rz[b]};
      const ContactForce f = HertzMindlin::evaluate(contact[b], c, h);
      Vec3 ti, tj;
      Rolling::evaluate(rolling[b], c, f, h, ti, tj);
      sx[b] = h.shear.x, sy[b] = h.shear.y, sz[b] = h.shear.z;
      if constexpr (Rolling::kSpring) rx[b] = h.rolling.x, ry[b] = h.rolling.y, rz[b] = h.rolling.z;
      const Vec3 nxft = cross(c.n, f.tangential);
      const Vec3 t_i = ti - c.lever_i * nxft, t_j = tj - c.lever_j * nxft;
      fx[b] = f.force.x, fy[b] = f.force.y, fz[b] = f.force.z;
      tix[b] = t_i.x, tiy[b] = t_i.y, tiz[b] = t_i.z;
      tjx[b] = t_j.x, tjy[b] = t_j.y, tjz[b] = t_j.z;
      overlap_ratio[b] = c.overlap / std::min(ri[b], rj[b]);
      stiffness_per_mass[b] = f.stiffness / c.m_eff;
    }
  }
};

}  // namespace grainscale::dem
