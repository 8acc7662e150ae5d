#pragma once
// The free rotations of a chunk of bodies, evaluated together so that the compiler vectorises them
// (Simulation::drift).
//
// Why: the five sub-rotations of the splitting (dem/rigid_rotation.hpp) are a long chain of
// dependent multiplications and divisions per body; one body at a time, their latency made the body
// loop most of `drift`, a fifth of a clump-bed step (perf, docs/performance.md). The caller copies the
// anisotropic bodies' orientation, momentum and inertia into these arrays (one per component, so a
// vector register holds 8 bodies), `rotate` runs free_rotation_step_series over them in one loop,
// and the caller copies the results back.
//
// Same numbers, bit for bit: the series variant performs free_rotation_step's operations in its
// order (IEEE division and square root are exact in vector form; no FMA: -ffp-contract=off). A body
// that turns beyond the sine series' range within a step (in_range == 0) gets free_rotation_step
// itself, from its old orientation, as before.
#include <cstdint>

#include "dem/rigid_rotation.hpp"

namespace grainscale::dem {

struct RotationBatch {
  static constexpr int kCapacity = 64;
  int size = 0;
  std::uint32_t body[kCapacity];
  alignas(64) double qw[kCapacity], qx[kCapacity], qy[kCapacity], qz[kCapacity];  // in and out
  alignas(64) double lx[kCapacity], ly[kCapacity], lz[kCapacity];                 // world momentum
  alignas(64) double ix[kCapacity], iy[kCapacity], iz[kCapacity];                 // principal moments
  alignas(64) double wx[kCapacity], wy[kCapacity], wz[kCapacity];                 // out: omega
  alignas(64) std::int64_t in_range[kCapacity];                                   // out

  void add(std::uint32_t k, const Quat& q, const Vec3& L, const Vec3& inertia) {
    const int c = size++;
    body[c] = k;
    qw[c] = q.w, qx[c] = q.x, qy[c] = q.y, qz[c] = q.z;
    lx[c] = L.x, ly[c] = L.y, lz[c] = L.z;
    ix[c] = inertia.x, iy[c] = inertia.y, iz[c] = inertia.z;
  }

  /// Free rotation for time h, then the angular velocity at the new orientation.
  void rotate(double h) {
#pragma GCC ivdep
    for (int c = 0; c < size; ++c) {
      Quat q{qw[c], qx[c], qy[c], qz[c]};
      const Vec3 L{lx[c], ly[c], lz[c]}, inertia{ix[c], iy[c], iz[c]};
      in_range[c] = free_rotation_step_series(q, L, inertia, h);
      const Vec3 w = angular_velocity(q, L, inertia);
      qw[c] = q.w, qx[c] = q.x, qy[c] = q.y, qz[c] = q.z;
      wx[c] = w.x, wy[c] = w.y, wz[c] = w.z;
    }
  }
};

/// The same for isotropic bodies (spheres, and clumps whose principal moments are equal): one exact
/// turn each, about omega = L / I (free_rotation_isotropic). One body at a time its square root and
/// five divisions, a chain of ~60 cycles, were a sixth of a loose-sphere bed's step (perf,
/// nineteenth session). Same numbers, bit for bit, as RotationBatch's: a body whose half angle is
/// beyond the series' range (in_range == 0) gets free_rotation_isotropic itself, from its old q.
struct IsotropicRotationBatch {
  static constexpr int kCapacity = RotationBatch::kCapacity;
  int size = 0;
  std::uint32_t body[kCapacity];
  alignas(64) double qw[kCapacity], qx[kCapacity], qy[kCapacity], qz[kCapacity];  // in and out
  alignas(64) double lx[kCapacity], ly[kCapacity], lz[kCapacity];                 // world momentum
  alignas(64) double inertia[kCapacity];                                          // the moment
  alignas(64) double wx[kCapacity], wy[kCapacity], wz[kCapacity];                 // out: omega
  alignas(64) std::int64_t in_range[kCapacity];                                   // out

  void add(std::uint32_t k, const Quat& q, const Vec3& L, double moment) {
    const int c = size++;
    body[c] = k;
    qw[c] = q.w, qx[c] = q.x, qy[c] = q.y, qz[c] = q.z;
    lx[c] = L.x, ly[c] = L.y, lz[c] = L.z;
    inertia[c] = moment;
  }

  /// omega = L / I (as (1 / I) L, the scalar path's order), then the free rotation for time h.
  void rotate(double h) {
#pragma GCC ivdep
    for (int c = 0; c < size; ++c) {
      Quat q{qw[c], qx[c], qy[c], qz[c]};
      const Vec3 w = (1.0 / inertia[c]) * Vec3{lx[c], ly[c], lz[c]};
      in_range[c] = free_rotation_isotropic_series(q, w, h);
      qw[c] = q.w, qx[c] = q.x, qy[c] = q.y, qz[c] = q.z;
      wx[c] = w.x, wy[c] = w.y, wz[c] = w.z;
    }
  }
};

}  // namespace grainscale::dem
