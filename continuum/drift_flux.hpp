#pragma once
// Relative drift of chaff through the grain: a flux q g(c) through each face, where q [m²/s] is the
// drift velocity's normal component integrated over the face and g(c) the mixture-theory mobility
// (Gray & Thornton 2005): g = c (1 − c) (the drift stops when either phase is absent), or the
// dilute-weighted g = c (1 − c)² of an asymmetric segregation flux (Gajjar & Gray 2014), whose
// drift is fastest for a few chaff flakes among much grain.
//
// g has a single maximum at c* (½, or ⅓), so the monotone Engquist–Osher flux is
//   F = q [ g(min(c⁻, c*)) + g(max(c⁺, c*)) − g(c*) ]    for q ≥ 0 (mirrored for q < 0),
// with c⁻, c⁺ the MUSCL states upstream and downstream of the face (segregation.hpp uses the same
// with c* = ½). F is zero at c = 0 and c = 1, so c stays in [0, 1]. |dF/dc| ≤ |q| max|g'| = |q|.
// The candidate effects of `grainscale loop` (lever arm, surface drift, wall mobility, pause creep,
// concentration-dependent segregation) are such drifts with different velocity fields.
#include <functional>
#include <span>

#include "continuum/flux_term.hpp"
#include "continuum/reconstruction.hpp"

namespace grainscale::continuum {

enum class Mobility { symmetric, dilute };  // c (1 − c)  |  c (1 − c)²

double mobility(Mobility m, double c);
/// Engquist–Osher face flux of q g(c) from the states before (c_minus) and after (c_plus) the face
/// in the direction of the face normal.
double drift_face_flux(Mobility m, double q, double c_minus, double c_plus);

/// Drift velocity fields on faces: `x_face_q(f, k)` and `s_face_q(i, m)` return q [m²/s] for
/// interior faces (x-faces f = 1..nx−1; σ-faces m = 1..nz−1). Either may be empty (no drift there).
struct DriftField {
  std::function<double(int, int)> x_face_q;
  std::function<double(int, int)> s_face_q;
};

/// q on every face, evaluated once and kept while the term's parameters, the grid and the face
/// shear rates stay the same (a fit runs thousands of steps with the same values).
class DriftCache {
 public:
  /// q per face for `drift`; `parameters` are the term's current values.
  const DriftCache& update(const TermContext& ctx, const DriftField& drift, const std::vector<double>& parameters);
  std::vector<double> x, s;  // per x-face and σ-face (0 where the field has no drift)

 private:
  std::vector<double> key_;
};

/// Add the drift fluxes; `states` is scratch space for the reconstruction.
void add_drift_fluxes(const TermContext& ctx, std::span<const double> c, const DriftCache& q, Mobility m,
                      Limiter limiter, FaceStates& states, FaceFluxes& out);
/// Add Σ_faces |q| / area per cell.
void add_drift_rate_bound(const TermContext& ctx, const DriftCache& q, std::span<double> rate);
/// Band half-width: MUSCL reaches two cells (2 nz in index across x-faces, 2 within a column).
int drift_half_bandwidth(const Grid& g, const DriftField& drift, Limiter limiter);

/// q through the upward σ-face (i, m) for a drift velocity (vx, vz): (vz − σ h_x vx) dx (normal·ds).
double s_face_drift(const Grid& g, int i, int m, double vx, double vz);
/// q through the x-face (f, k) for a horizontal drift velocity vx: vx h dσ.
double x_face_drift(const Grid& g, int f, double vx);

}  // namespace grainscale::continuum
