#pragma once
// Lever-arm accelerations of a container off its rotation axis. In the container frame the grain
// feels g_eff = g − α × r − ω × (ω × r) (r from the axis; Euler and centrifugal terms). Over a
// symmetric tilting cycle the tilt's own lean of g averages out; the lever arm's does not:
// effective_gravity.hpp gives the cycle-mean anomaly a(x, z) (G2)–(G3), the centrifugal lean away
// from the axis and the Euler term's one-sided avalanching (more normal load at one end of the
// swing, less at the other). Light chaff segregates against g_eff (segregation.hpp: against g,
// w_s = S γ̇), so its cycle-mean drift relative to the grain is
//   v = −S_l γ̇ (a_x, a_z)                                                                (L1)
// carried as q c (1 − c) (drift_flux.hpp). With `rate` > 0 that rate [1/s] replaces γ̇: a bed the
// swing moves throughout (the Euler term shaking it), which the cycle-mean γ̇ averages out, given
// e.g. the swing's angular frequency. S_l [m] is the segregation length for this forcing
// (fitted; the same order as segregation.S if the mechanism is the same). The motion's ⟨ω²⟩ and
// ⟨α²⟩ and the axis position (x_a, z_a) in the container frame come from the experiment
// (`grainscale loop` reads them from the DEM scenario); μ, the bed's static friction (tan of its
// repose angle), is the user's (0: the mean slope). With ⟨α²⟩ = 0 the anomaly is the centrifugal
// part alone, a = ⟨ω²⟩ r / g: for the report's box (24°, 0.1 Hz, 4 s pauses, ⟨ω²⟩ ≈ 0.019 1/s²)
// 0.002 per metre of arm, small in a platform box, 0.02–0.05 in a ship's hold 10–20 m from the
// roll axis. For a box 0.8–1.0 m from the axis tilting ±35° at 0.5 Hz (studies/loop_lever_arm/)
// the Euler part wins: a_x = −0.10 to −0.21 (μ = 0), the bed leans towards the axis and the chaff
// drifts to the far end.
//
// With `layer` δ > 0 the drift acts only in the top δ of the bed:
//   v = −S_l γ̇ a(x, z)  where z > h(x) − δ,   0 below                                      (L2)
// the lean drives the flowing surface layer, not the plug beneath it: at ±35° the bed below a
// few grains rocks with the box (the on-axis DEM of studies/loop_lever_arm/ keeps its balls where
// the pour left them), while the layer avalanches one way at the swing's weak end. On that DEM's
// off-axis run a 20 mm layer (three 2× grain lengths) explains more of the far-end pile than the
// whole depth does (docs/loop.md). δ = 0 (the default) is (L1) throughout.
#include "continuum/drift_flux.hpp"
#include "continuum/terms/effective_gravity.hpp"

namespace grainscale::continuum {

class LeverArm final : public FluxTerm {
 public:
  explicit LeverArm(Limiter limiter);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;
  /// (L1) at (x, z) for shear rate γ̇: the drift velocity (vx, vz) [m/s] (evaluated directly, not
  /// from the table the fluxes use).
  std::pair<double, double> drift(double x, double z, double shear_rate) const;

 private:
  CycleMotion motion() const;
  /// The rate the drift scales with: `rate` if set, else the local shear rate.
  double mobility_rate(double shear_rate) const;
  const AnomalyTable& table(const Grid& g) const;
  DriftField field(const TermContext& ctx) const;
  const DriftCache& faces_q(const TermContext& ctx) const;
  Limiter limiter_;
  mutable FaceStates states_;
  mutable DriftCache cache_;
  mutable AnomalyTable table_;
};

}  // namespace grainscale::continuum
