#pragma once
// A batch of sphere-wall contacts, evaluated together so that the compiler vectorises the contact
// models (dem/force_field.cpp, pass 2): the wall twin of PairBatch (dem/pair_batch.hpp).
//
// Why: the models' square roots and divisions, one contact at a time, left the wall contacts at
// 18-24 % of a settled sphere bed on its floor (perf). Pass 2 finds a sphere's wall contacts, matches
// their histories and works out the kinematics; `evaluate` runs the models over the batch; the
// caller adds each contact to its sphere in the order found.
//
// Same numbers, bit for bit, as one at a time, for the reasons PairBatch gives; nothing is summed
// across contacts here (tests/dem/test_wall_batch.cpp).
#include <cstdint>
#include <limits>

#include "dem/contact/contact_kinematics.hpp"
#include "dem/contact/hertz_mindlin.hpp"
#include "dem/force_field.hpp"

namespace grainscale::dem {

template <class Rolling>
struct WallBatch {
  static constexpr int kCapacity = 32;
  int size = 0;

  // In: the contact (normal from the wall to the sphere's centre, overlap), the sphere's radius,
  // angular velocity, mass and moment of inertia, the wall's angular velocity, and the relative
  // velocity at the contact point, v_i - (r_i - overlap) omega_i x n - v_wall(point).
  alignas(64) double nx[kCapacity], ny[kCapacity], nz[kCapacity], overlap[kCapacity], ri[kCapacity];
  alignas(64) double vx[kCapacity], vy[kCapacity], vz[kCapacity];
  alignas(64) double wix[kCapacity], wiy[kCapacity], wiz[kCapacity];
  alignas(64) double wjx[kCapacity], wjy[kCapacity], wjz[kCapacity];
  alignas(64) double mi[kCapacity], ii[kCapacity];
  HertzMindlin::Params contact[kCapacity];
  typename Rolling::Params rolling[kCapacity];
  // In and out: the contact's history (one array per component).
  alignas(64) double sx[kCapacity], sy[kCapacity], sz[kCapacity], rx[kCapacity], ry[kCapacity], rz[kCapacity];
  // Where it goes: the sphere's slot, and the wall slot that keeps the history.
  std::uint32_t owner[kCapacity];
  WallSlot* slot[kCapacity];
  // Out: force on the sphere, its torque (rolling torque plus lever x tangential force).
  alignas(64) double fx[kCapacity], fy[kCapacity], fz[kCapacity];
  alignas(64) double tx[kCapacity], ty[kCapacity], tz[kCapacity];
  // Out, for the monitors: overlap / radius, normal stiffness / mass.
  alignas(64) double overlap_ratio[kCapacity], stiffness_per_mass[kCapacity];

  /// The kinematics of contact b as the models see it (a wall: lever 0, infinite mass and inertia).
  static ContactKinematics kinematics(const WallBatch& w, int b, double dt) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    ContactKinematics c;
    c.n = {w.nx[b], w.ny[b], w.nz[b]};
    c.overlap = w.overlap[b];
    c.lever_i = w.ri[b] - c.overlap;
    c.lever_j = 0;
    c.omega_i = {w.wix[b], w.wiy[b], w.wiz[b]};
    c.omega_j = {w.wjx[b], w.wjy[b], w.wjz[b]};
    c.v_rel = {w.vx[b], w.vy[b], w.vz[b]};
    c.r_eff = w.ri[b];
    c.mass_i = c.m_eff = w.mi[b];
    c.mass_j = kInf;
    c.inertia_i = w.ii[b];
    c.inertia_j = kInf;
    c.dt = dt;
    return c;
  }

  /// Runs the contact and rolling models over the batch.
  void evaluate(double dt) {
    // (No `omp simd`, as in PairBatch: its per-lane struct copies stop GCC vectorising.)
#pragma GCC ivdep
    for (int b = 0; b < size; ++b) {
      const ContactKinematics c = kinematics(*this, b, dt);
      ContactHistory h{{sx[b], sy[b], sz[b]}, {rx[b], ry[b], rz[b]}};
      const ContactForce f = HertzMindlin::evaluate(contact[b], c, h);
      Vec3 ti, tj;
      Rolling::evaluate(rolling[b], c, f, h, ti, tj);
      sx[b] = h.shear.x, sy[b] = h.shear.y, sz[b] = h.shear.z;
      rx[b] = h.rolling.x, ry[b] = h.rolling.y, rz[b] = h.rolling.z;
      const Vec3 t = ti - c.lever_i * cross(c.n, f.tangential);
      fx[b] = f.force.x, fy[b] = f.force.y, fz[b] = f.force.z;
      tx[b] = t.x, ty[b] = t.y, tz[b] = t.z;
      overlap_ratio[b] = c.overlap / ri[b];
      stiffness_per_mass[b] = f.stiffness / c.m_eff;
    }
  }
};

}  // namespace grainscale::dem
