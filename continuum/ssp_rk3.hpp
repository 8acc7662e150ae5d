#pragma once
// Third-order strong-stability-preserving Runge–Kutta (Shu & Osher 1988):
//   u¹ = uⁿ + dt L(uⁿ),  u² = ¾ uⁿ + ¼ (u¹ + dt L(u¹)),  uⁿ⁺¹ = ⅓ uⁿ + ⅔ (u² + dt L(u²)).
// Each stage is a convex combination of forward-Euler steps, so whatever bound forward Euler keeps
// under dt · max_rate ≤ CFL (c in [0, 1] for monotone fluxes) the whole step keeps too. Linear
// invariants (total chaff) are kept to round-off. Explicit: for cross-checks and fits on coarse grids.
#include "continuum/integrator.hpp"

namespace grainscale::continuum {

class SspRk3 final : public TimeIntegrator {
 public:
  SspRk3(const Model& model, IntegratorSettings settings);
  void advance(double t0, double t1, std::vector<double>& c) override;
  void restart() override {}
  std::string name() const override { return "ssp_rk3"; }
  IntegratorStats stats() const override { return stats_; }

 private:
  const Model& model_;
  IntegratorSettings settings_;
  IntegratorStats stats_;
  std::vector<double> k_, u1_, u2_;
};

}  // namespace grainscale::continuum
