#pragma once
// The slow-time chaff model: cycle-averaged drift and dispersion, per face of the chaff grid,
// extracted from resolved motion cycles (docs/hold_prediction.md, "Days of motion").
//
// Over resolved cycles j the cycle-mean flux through each face, F̄_j = (1/T) ∫_cycle F dt (all flux
// terms together: advection, segregation, diffusion), is regressed on the cycle-mean concentrations
// on the two sides of the face, c̄ = (c_L + c_R)/2:
//
//   F̄ = V c̄ (1 − c̄) − K (c_R − c_L)                                                        (A1)
//
// V [m²/s] is the face's drift (the rectified transport the oscillating flow and segregation
// produce, which the Eulerian mean of the flow misses), K [m²/s] its dispersion. The cycle-mean
// flow carries no net bulk through a face, so the drift is chaff moving against grain: an exchange
// flux that must vanish where either is absent, the c (1 − c) of Gray & Thornton (2005) as in the
// segregation term. A drift linear in c̄ (the first form used here) has no such bound: in the full
// Handysize hold it piled chaff to c = 6.9 in one surface cell over a day.
// Least squares per face over the cycles; K is fitted only where it is identifiable (the two
// regressors not collinear, and c_R − c_L resolved: rms ≥ 1e-5 rms c̄), and raised to at least
// |V|/2. Then ∂F̄/∂c_L = V (1 − 2c̄)/2 + K ≥ 0 and ∂F̄/∂c_R ≤ 0 for c̄ in [0, 1], and F̄ = 0 at
// c = 0 and c = 1 on both sides: a monotone flux, so an explicit step under the CFL bound keeps c
// in [0, 1] (BDF to within its tolerance). Boundary faces carry no flux, so chaff is conserved to
// round-off as in every flux term. Not registered (built from a resolved run, not YAML).
#include <vector>

#include "continuum/flux_term.hpp"

namespace grainscale::continuum::closure {

/// Accumulates cycle means of fluxes and concentrations over resolved cycles, then fits (A1).
class CycleFluxSampler {
 public:
  explicit CycleFluxSampler(const Grid& grid) : grid_(grid) {}
  /// One sample within the current cycle (trapezoid in time): fluxes and c at time t.
  void sample(double t, const FaceFluxes& fluxes, const std::vector<double>& c);
  /// Close the current cycle (its mean becomes one regression row).
  void end_cycle();
  int cycles() const { return static_cast<int>(rows_c_.size()); }
  /// The fitted drift V and dispersion K per x-face and σ-face (face numbering of face_coefficients.hpp).
  void fit(std::vector<double>& vx, std::vector<double>& kx, std::vector<double>& vs, std::vector<double>& ks) const;

 private:
  Grid grid_;
  double t_last_ = 0, span_ = 0;
  bool have_last_ = false;
  FaceFluxes last_f_, sum_f_;
  std::vector<double> last_c_, sum_c_;
  std::vector<FaceFluxes> rows_f_;
  std::vector<std::vector<double>> rows_c_;
};

class CycleAveragedTransport final : public FluxTerm {
 public:
  CycleAveragedTransport(std::vector<double> vx, std::vector<double> kx, std::vector<double> vs, std::vector<double> ks);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override { return grid.nz() + 1; }

 private:
  std::vector<double> vx_, kx_, vs_, ks_;
};

}  // namespace grainscale::continuum::closure
