#pragma once
// The bulk motion the chaff is carried by, in the container frame: a stream function ψ(x, z, t) and
// the shear rate γ̇(x, z, t). The velocity is u = ∂ψ/∂z, w = −∂ψ/∂x (incompressible bulk in the
// x–z cross-section). Supplying ψ rather than (u, w) makes the discrete volume fluxes through the
// faces of every cell sum to zero exactly (they are differences of ψ at the cell corners), so a
// uniform c stays uniform and c cannot leave [0, 1] through a spurious divergence. ψ must vanish on
// the walls, the floor and the free surface (no flow through them).
//
// Implementations: analytic flows (analytic_flows.hpp) for tests and synthetic studies, gridded
// coarse-grained DEM fields (gridded_flow.hpp); a flow closure can implement this too.
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
};

}  // namespace grainscale::continuum
