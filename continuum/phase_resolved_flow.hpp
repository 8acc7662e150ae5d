#pragma once
// Coarse-grained DEM fields given per phase of the container's motion (grainscale cg with
// averaging mode `phase`: one frame per phase bin, docs/coarsegrain_layout.md), interpolated in
// space within each phase (gridded_flow.hpp, G1) and in phase by periodic cubic Hermite
// (Catmull–Rom) interpolation between the bin centres, periodic in the motion period T:
//   φ(t) = frac((t − t0) / T),   ·(x, t) = Σ_j W_j(φ) ·_j(x),   Σ_j W_j = 1,
// over the four bins around φ. Catmull–Rom rather than linear, because the surface velocity ∂h/∂t
// is a derivative in time: linear interpolation makes it piecewise constant, wrong by O(Δφ) at the
// bin centres (20 % with 16 bins); the cubic is C¹ with O(Δφ²) error in ∂h/∂t.
// ψ and γ̇ are blended at equal σ = z / h(x, t) (γ̇ clipped at 0: the weights can be negative).
//
// Moving surface (`moving` true): h(x, t) = Σ W_j h_j(x). The phase fields' own ψ vanish at their
// surfaces (G1), so the bulk flux that moves the surface is added back from the kinematic
// condition (flow.hpp):
//   q(x, t) = −∫₀ˣ ∂h/∂t dx′ = −Σ_j W_j′(t) ∫₀ˣ h_j dx′,   ψ += q(x, t) σ,                (P1)
// spread over the depth as a plug flow (u = q / h). Phase-averaged surfaces of a closed box enclose
// slightly different bed areas (noise, dilatancy); each phase's surface is scaled to the mean area
// first so that q vanishes at both end walls (the largest scale correction is reported by
// area_correction()). Fixed surface (`moving` false): the surface is the mean over the phases and
// ψ has no net column flux.
#include <string>
#include <vector>

#include "continuum/flow.hpp"
#include "continuum/gridded_flow.hpp"

namespace grainscale::continuum {

class PhaseResolvedFlow final : public Flow {
 public:
  struct Phase {
    double phase;  // bin centre [cycles], in [0, 1)
    GriddedFlow field;
  };
  /// `phases`: at least two, distinct phases; `period` T [s] > 0; `t0` [s] is phase 0.
  PhaseResolvedFlow(std::vector<Phase> phases, double period, double t0, bool moving);
  /// Every phase frame of a coarse-graining field file (GriddedFlow::phase_frames); `length` = L.
  static PhaseResolvedFlow load(const std::string& file, double length, double period, double t0, bool moving);

  double stream_function(double x, double z, double t) const override;
  double shear_rate(double x, double z, double t) const override;
  bool steady() const override { return false; }
  bool moving_surface() const override { return moving_; }
  double surface_height(double x, double t) const override;
  /// h at x: at time t if the surface moves, else the mean surface.
  double surface_at(double x, double t) const;
  /// q(x, t) of (P1) (0 for a fixed surface).
  double surface_flux(double x, double t) const;

  int phases() const { return static_cast<int>(phases_.size()); }
  double period() const { return period_; }
  /// Largest |factor − 1| applied to a phase's surface to equalise the bed areas.
  double area_correction() const { return area_correction_; }

 private:
  struct Bracket {
    int phase[4];      // the bins before, at/below, above and after φ
    double w[4];       // Catmull–Rom weights W_j
    double w_rate[4];  // dW_j/dt [1/s]
  };
  Bracket bracket(double t) const;
  double mean_surface(double x) const;

  std::vector<Phase> phases_;  // sorted by phase
  double period_, t0_;
  bool moving_;
  double area_correction_ = 0;
};

}  // namespace grainscale::continuum
