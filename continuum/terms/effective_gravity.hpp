#pragma once
// The cycle-mean anomaly of the effective gravity in a container that tilts about an axis it is not
// on. In the container frame (x along the floor, z up, the axis along y at (x_a, z_a)) the grain at
// r = (x − x_a, z − z_a) feels
//   g_eff = g_c(θ) − α × r − ω × (ω × r)
//         = (g sin θ − θ'' r_z + θ'² r_x,  −g cos θ + θ'' r_x + θ'² r_z)                (G1)
// (θ the tilt about y, ω = θ' ŷ, α = θ'' ŷ). The motion is represented by the harmonic
// θ = A sin φ with the same cycle means ⟨ω²⟩ and ⟨α²⟩: Ω² = ⟨α²⟩/⟨ω²⟩, A² = 2 ⟨ω²⟩/Ω² (exact
// for the cosine platform; for a profile with pauses it keeps the energy of the motion).
//
// A bed flows when the slope it feels, e = g_eff,x / (−g_eff,z), exceeds its static friction μ
// (the tangent of its angle of repose; Jop, Forterre & Pouliquen, Nature 441 (2006) 727: no flow
// below μ_s). Over a symmetric tilt without a lever arm the slope excess sgn(e) (|e| − μ)⁺ averages
// to zero; off the axis it does not: the Euler term α × r adds to the normal load at one end of the
// swing and takes it away at the other (θ'' = −Ω² θ), so the bed avalanches mostly one way, and
// the centrifugal term leans g_eff away from the axis. The anomaly is
//   a_x = ⟨sgn(e) (|e| − μ)⁺⟩ − ⟨sgn(tan θ) (|tan θ| − μ)⁺⟩                          (G2)
//   a_z = −(⟨−g_eff,z⟩ / g − ⟨cos θ⟩) = ⟨ω²⟩ r_z / g                                  (G3)
// (a points where the extra pull goes: a_x > 0 leans the bed towards +x; a_z > 0 pulls it up).
// μ = 0 gives the mean slope ⟨e⟩. With ⟨α²⟩ = 0 (no angular acceleration known, or a steady
// rotation) the anomaly is the centrifugal part alone, a = ⟨ω²⟩ r / g. That is not the limit of a
// small swing: for θ = A sin φ the Euler term's rectified slope −Ω² ⟨θ²⟩ r_x / g cancels the
// centrifugal ⟨θ'²⟩ r_x / g, and a_x is O(A⁴) (tests/continuum/test_effective_gravity.cpp).
//
// While g_eff,z ≥ 0 the bed is lifted off its floor; e is then capped at ±kMaxSlope.
#include <utility>
#include <vector>

namespace grainscale::continuum {

struct CycleMotion {
  double omega2 = 0;  // ⟨ω²⟩ [1/s²]
  double alpha2 = 0;  // ⟨α²⟩ [1/s⁴]; 0: centrifugal part only
  double axis_x = 0, axis_z = 0;  // the axis in the container frame [m]
  double mu = 0;      // static friction of the bed (tan of its repose angle); 0: the mean slope
  bool operator==(const CycleMotion&) const = default;
};

inline constexpr double kMaxSlope = 10.0;

/// (G2)–(G3) at (x, z) [m]: (a_x, a_z), dimensionless (fractions of g), by the midpoint rule over
/// `samples` phases of the cycle.
std::pair<double, double> effective_gravity_anomaly(const CycleMotion& m, double x, double z, int samples = 256);

/// (G2)–(G3) tabulated on a regular (x, z) lattice and interpolated bilinearly (a smooth field; the
/// table is built once per motion, not once per face and time step). Outside the lattice: clamped.
class AnomalyTable {
 public:
  AnomalyTable() = default;
  AnomalyTable(const CycleMotion& m, double x_lo, double x_hi, double z_lo, double z_hi, int nx = 33, int nz = 17);
  std::pair<double, double> at(double x, double z) const;
  const CycleMotion& motion() const { return motion_; }
  bool covers(double x_lo, double x_hi, double z_lo, double z_hi) const;

 private:
  CycleMotion motion_;
  double x_lo_ = 0, x_hi_ = 0, z_lo_ = 0, z_hi_ = 0;
  int nx_ = 0, nz_ = 0;
  std::vector<double> ax_, az_;
};

}  // namespace grainscale::continuum
