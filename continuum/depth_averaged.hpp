#pragma once
// The 1-D depth-averaged variant of the continuum model (issue 7), for quick fits: one unknown per
// column, the chaff inventory I(x, t) = ∫₀ʰ c dz [m]. Derivation (docs/continuum.md, "Depth-averaged
// variant"): integrating (C1) over the depth, with no chaff flux through the floor and the (possibly
// moving) surface, leaves the exact conservation law
//   ∂I/∂t + ∂F/∂x = 0,   F = ∫₀ʰ (u c − D ∂c/∂x|_z) dz.                                (A1)
// The closure is the vertical profile. When segregation and vertical mixing are fast compared with
// the horizontal transport (vertical time h/w_s, h²/D ≪ horizontal time L/u), each column relaxes
// to the zero-flux balance of (C1) in z, w_s c (1 − c) = D ∂c/∂z, i.e.
//   c(z) = 1 / (1 + exp(−(Λ(z) − μ))),   Λ(z) = ∫₀ᶻ S γ̇ / (C γ̇ d² + D₀) dz′,             (A2)
// (the logistic profile of the steady segregation–diffusion column; Fan et al. 2014 use its uniform-
// γ̇ form), with μ fixed by ∫ c dz = I. The segregation source that lifts chaff into the surface
// layer is thereby instantaneous: it is slaved into (A2), and the observed surface layer is read
// off the profile. F in (A1) is then a nonlinear function of I: advective drift ∫ u c dz (chaff high
// in the column goes with the surface flow) and dispersion −∫ D ∂c/∂x dz.
//
// Discretisation: the profile is sampled at N = nz·n_sub equal σ-levels (N ≥ 64) of every column
// (midpoint rule, so the samples integrate to I exactly after the solve for μ). Face fluxes are
// those of the 2-D model (advection.hpp, diffusion_stencil.hpp D1) on N layers with the profiles
// as layer values: upwind per layer from MUSCL face profiles (the inventory fraction θ = I/h is
// reconstructed with the advection term's limiter and the face profile is (A2) with the face's
// γ̇ and depth), diffusion from the two column profiles compared at equal σ with the sloping-
// surface cross term. (A1) in finite volumes conserves Σ I dx to round-off.
// Terms: advection, segregation, shear_diffusion, background_diffusion (their parameters keep
// their names, so fits address them as for the 2-D model).
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "continuum/face_coefficients.hpp"
#include "continuum/flow.hpp"
#include "continuum/grid.hpp"
#include "continuum/reconstruction.hpp"

namespace grainscale::continuum {

class Model;

/// (A2): given Λ at the sample points (dimensionless, increasing with z for S > 0) and the mean
/// θ ∈ [0, 1] of c over the samples, fill c with the logistic profile of mean θ. `mu` (optional):
/// in, a starting guess for μ (used if inside the bracket); out, the μ found.
void equilibrium_profile(std::span<const double> Lambda, double theta, std::span<double> c, double* mu = nullptr);

class DepthAveraged {
 public:
  struct Coefficients {
    double S = 0;               // segregation.S [m]
    double per_shear = 0;       // C d² [m²]
    double D0 = 0;              // [m²/s]
    double velocity_scale = 0;  // 0 without an advection term
    Limiter limiter = Limiter::first_order;
  };
  static Coefficients coefficients(const Model& model);
  static bool supports(const std::string& term_name);
  static std::string supported_terms();
  /// Face fluxes reach two columns either side (MUSCL).
  static int half_bandwidth() { return 2; }

  explicit DepthAveraged(const Grid& grid);
  ~DepthAveraged();

  /// Cycle averaging (model.cycle_average): the face fluxes are averaged over `phases` equally
  /// spaced times (p + ½) T / phases of the motion period T at fixed I, so the rhs no longer depends
  /// on t and an integrator can step over many cycles (docs/continuum.md, "Cycle averaging").
  /// phases = 0: off (the instantaneous flow).
  void set_cycle_average(double period, int phases);
  int cycle_phases() const { return cycle_phases_; }

  /// I_i = Σ_k c_ik dσ h̄_i.
  std::vector<double> inventory(const Grid& g, std::span<const double> c) const;
  /// Cell averages of the profile (A2) on g.
  std::vector<double> concentration(const Grid& g, const Flow& flow, double t, const Coefficients& k,
                                    std::span<const double> I) const;
  /// F through the x-faces f = 0..nx (zero at the walls) [m²/s].
  void fluxes(const Grid& g, const Flow& flow, double t, const Coefficients& k, std::span<const double> I,
              std::vector<double>& F) const;
  void rhs(const Grid& g, const Flow& flow, double t, const Coefficients& k, std::span<const double> I,
           std::span<double> dIdt) const;
  double max_rate(const Grid& g, const Flow& flow, double t, const Coefficients& k) const;
  /// Band Jacobian by grouped difference quotients of the face fluxes (column sums zero).
  void jacobian(const Grid& g, const Flow& flow, double t, const Coefficients& k, std::span<const double> I, int b,
                const std::function<void(std::size_t, std::size_t, double)>& add) const;

  int samples() const { return samples_; }

 private:
  struct Cache;  // flow on the fine grid at one time, μ and Λ per profile slot
  Cache& cache(std::size_t j) const;
  void prepare(Cache& c, const Grid& g, const Flow& flow, double t) const;
  /// Λ at the samples from γ̇ samples over depth h.
  void lambda(const Coefficients& k, const double* shear, double h, std::vector<double>& out) const;
  /// The profile of one slot: column i is 3 i, the face profiles of face f are 3 f + 1 (left) and
  /// 3 f + 2 (right); each slot keeps its μ (Newton's start) and its Λ (while coefficients and flow
  /// stay the same).
  void profile(Cache& cache, const Coefficients& k, int slot, const double* shear, double h, double theta,
               std::span<double> c) const;
  void instantaneous_fluxes(Cache& cache, const Grid& g, const Flow& flow, double t, const Coefficients& k,
                            std::span<const double> I, std::vector<double>& F) const;
  double instantaneous_max_rate(Cache& cache, const Grid& g, const Flow& flow, double t, const Coefficients& k) const;
  /// The grid at time t (the surface moves) or g.
  static Grid grid_at(const Grid& g, const Flow& flow, double t);

  int nx_, nsub_, samples_;
  int cycle_phases_ = 0;
  double cycle_period_ = 0;
  // caches_[0]: the instantaneous flow (and outputs); caches_[1 + p]: averaging phase p.
  mutable std::vector<std::unique_ptr<Cache>> caches_;
  mutable std::vector<double> scratch_lambda_, col_c_, face_l_, face_r_, F_base_, F_pert_, F_phase_;
};

}  // namespace grainscale::continuum
