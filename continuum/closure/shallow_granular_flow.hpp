#pragma once
// Depth-averaged granular flow on the floor of a tilting container, in the container frame: a
// Savage–Hutter type model (Savage & Hutter, J. Fluid Mech. 199, 1989; moving frames: Gray, Wieland &
// Hutter 1999) for the bed depth h(x, t) and the surface speed u(x, t), with the velocity profile
// through the depth
//
//   u(x, z, t) = u_s(x, t) e^{−(h − z)/ℓ}                                                    (S0)
//
// (a flowing layer of e-folding depth ℓ over slower grain; ℓ = ∞ is plug flow, classical SH).
// The volume flux is q = a(h) u_s with a(h) = ∫₀ʰ e^{−(h−z)/ℓ} dz = ℓ (1 − e^{−h/ℓ}), and the
// equations, per unit width, are
//
//   ∂h/∂t + ∂(a u_s)/∂x = 0                                                                  (S1)
//   ∂u_s/∂t + u_s ∂u_s/∂x = g_t − K g_n ∂h/∂x − N μ(h, I) sgn(u_s)      (moving)             (S2)
//   u_s = 0  while  |g_t − K g_n ∂h/∂x| ≤ N μ_start(h)                  (Coulomb yield)
//   (μ_start = μ_s without start/stop hysteresis; with it, bed_friction.hpp (F3), a face at rest
//   needs μ_start > μ_s to start, a moving face stops where the drive falls to N μ_s)
//   N = g_n + (1 − e^{−h/ℓ}) g_t ∂h/∂x                                  (normal load)        (S3)
//
// (S3): a plug (h ≪ ℓ) presses on the floor with g_n, as in SH; a surface layer (h ≫ ℓ) flows along
// the free surface and presses on it with g_eff · n_surface ∝ g_n + g_t ∂h/∂x. With the latter the
// yield condition of a planar surface is exact, tan(θ − β) ≤ μ_s for a floor tilted by θ and a
// surface sloping by β = atan ∂h/∂x relative to the floor; SH's floor-normal form would give
// tan θ − tan β ≤ μ_s, 3° off at θ = 35°, φ = 26.7°. The common factor (1 + h_x²)^{−1/2} of drive
// and load is dropped (it changes speeds by cos β, not the threshold).
// g_t, g_n: gravity along and into the floor in the container frame, including the lever-arm
// accelerations (container_gravity.hpp); μ from bed_friction.hpp, including the side walls' μ_w a/W
// for a channel of width W (side_wall_friction.hpp, (W1); none without a width); the earth-pressure
// coefficient K is 1 (hydrostatic) unless Savage–Hutter's active/passive K is asked for
// (earth_pressure.hpp, (K1): `earth_pressure: savage_hutter`); the shape factor of ∫u² dz is taken as 1. For ℓ = ∞, (S1)–(S2) are the SH
// equations (mass and velocity form) on a flat floor. For h ≫ ℓ they are a shallow layer of
// thickness ℓ flowing over, and exchanging mass with, static grain (a BCRE-type picture, Bouchaud et
// al. 1994): erosion and deposition are the change of h.
//
// Discretisation: staggered finite volumes (Stelling & Duinmeijer, Int. J. Numer. Meth. Fluids 43,
// 2003): h at cell centres, u_s at faces, end walls at the first and last face (u_s = 0 there).
// Per step: u* = u + Δt (g_t − g_n Δh/Δx − u ∂u/∂x), advection in the momentum-conservative upwind
// form of Stelling & Duinmeijer (right front speeds on a dry floor); Coulomb friction implicitly,
// u_new = sgn(u*) v with v + Δt g_n μ(v) = |u*| if |u*| > Δt g_n μ_yield (μ_start at rest, μ_s moving), else 0 — so a bed below the
// threshold stays exactly at rest (no numerical diffusion of h, unlike collocated Rusanov/HLL);
// then h_i −= Δt/Δx (F_{i+1/2} − F_{i−1/2}) with F = a(h_upwind) u_new. Mass is conserved to
// round-off (wall fluxes are zero) and h stays ≥ 0 for Δt (|u| + √(g_n a)) ≤ cfl Δx, cfl ≤ 0.5.
// An optional ceiling (a full hold's deck) blocks flow into a cell that is full.
#include <functional>
#include <limits>
#include <vector>

#include "continuum/closure/bed_friction.hpp"
#include "continuum/closure/container_gravity.hpp"

namespace grainscale::continuum::closure {

struct SectionSettings {
  double length = 1;   // container length along the section [m]
  int nx = 100;        // cells
  BedFriction friction;
  double ceiling = std::numeric_limits<double>::infinity();  // height of the deck above the floor [m]
  double cfl = 0.45;
  double max_dt = std::numeric_limits<double>::infinity();   // e.g. to resolve the motion (period / 100)
  double dry_depth = 1e-9;                                    // cells shallower than this do not feed a flux [m]
};

class ShallowGranularFlow {
 public:
  /// `depth`: h at the nx cell centres (≥ 0), at time t0.
  ShallowGranularFlow(SectionSettings settings, ContainerGravity gravity, std::vector<double> depth, double t0 = 0);

  double time() const { return t_; }
  int nx() const { return s_.nx; }
  double dx() const { return dx_; }
  double length() const { return s_.length; }
  const SectionSettings& settings() const { return s_; }
  const ContainerGravity& gravity() const { return gravity_; }
  /// h at cell centres [m].
  const std::vector<double>& depth() const { return h_; }
  /// u_s at the nx + 1 faces (0 at the walls) [m/s].
  const std::vector<double>& surface_speed() const { return u_; }
  /// Volume flux q = a(h_upwind) u_s at the faces [m²/s], as used in the last step's mass update.
  const std::vector<double>& flux() const { return q_; }
  /// Σ h Δx [m²].
  double volume() const;
  long steps() const { return steps_; }

  /// Largest stable step at the current state (CFL), capped by settings.max_dt.
  double stable_dt() const;
  /// One step of size dt (no CFL check).
  void step(double dt);
  /// Step to t1 exactly with steps ≤ stable_dt(); `after_step` sees the state after each step.
  void advance(double t1, const std::function<void(const ShallowGranularFlow&)>& after_step = {});

 private:
  SectionSettings s_;
  ContainerGravity gravity_;
  double dx_;
  double t_;
  long steps_ = 0;
  std::vector<double> h_, u_, q_, a_;
  EarthPressure pressure_;  // K's limits (1, 1 unless Savage–Hutter's)
};

}  // namespace grainscale::continuum::closure
