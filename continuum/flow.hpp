#pragma once
// The bulk motion the chaff is carried by, in the container frame: a stream function ψ(x, z, t) and
// the shear rate γ̇(x, z, t). The velocity is u = ∂ψ/∂z, w = −∂ψ/∂x (incompressible bulk in the
// x–z cross-section). Supplying ψ rather than (u, w) makes the discrete volume fluxes through the
// faces of every cell sum to zero exactly (they are differences of ψ at the cell corners), so a
// uniform c stays uniform and c cannot leave [0, 1] through a spurious divergence. ψ must vanish on
// the walls, the floor and the free surface (no flow through them).
//
// Moving free surface h(x, t) (moving_surface() true): ψ still vanishes on the end walls and the
// floor, but on the surface it equals the bulk flux under it, q(x, t) = ψ(x, h(x, t), t), and h must
// obey the kinematic condition ∂h/∂t + ∂q/∂x = 0 (the surface moves with the bulk). The grid follows
// h (σ = z / h), and the model solves d(A c)/dt = −Σ faces (flux relative to the moving face)
// (docs/continuum.md, "Moving free surface"). A moving-surface flow is not steady().
//
// Implementations: analytic flows (analytic_flows.hpp) for tests and synthetic studies, gridded
// coarse-grained DEM fields (gridded_flow.hpp); a flow closure can implement this too.
#include <stdexcept>

namespace grainscale::continuum {

class Flow {
 public:
  virtual ~Flow() = default;
  /// ψ [m²/s] at (x, z) [m], time t [s].
  virtual double stream_function(double x, double z, double t) const = 0;
  /// γ̇ ≥ 0 [1/s].
  virtual double shear_rate(double x, double z, double t) const = 0;
  /// True if neither ψ nor γ̇ depends on t (face coefficients are then computed once).
  virtual bool steady() const = 0;
  /// True if the free surface moves; then surface_height() gives h(x, t) and the grid follows it.
  virtual bool moving_surface() const { return false; }
  /// h(x, t) [m] above the floor, x in [0, L] (only called when moving_surface()).
  virtual double surface_height(double x, double t) const {
    (void)x;
    (void)t;
    throw std::logic_error("continuum Flow: surface_height() called on a flow without a moving surface");
  }
};

}  // namespace grainscale::continuum
