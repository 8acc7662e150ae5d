#pragma once
// SUNDIALS ARKODE (ARKStep) additive Runge–Kutta IMEX: the diffusive terms (FluxTerm::
// implicit_in_imex: shear and background diffusion) implicit, everything else (advection,
// segregation, sources, the moving surface's column areas) explicit, with ARKODE's default
// ARK4(3)6L[2]SA pair (Kennedy & Carpenter 2003) and adaptive steps. The implicit stages use Newton
// with a band direct solver on the conservative face-flux Jacobian of the implicit part
// (conservative_jacobian.hpp) and linear-solution scaling switched off, so, as with CVODE, the
// total chaff is kept to round-off. Useful when fine vertical resolution makes diffusion stiff
// while advection sets a mild explicit limit. The depth-averaged model is not split (all implicit).
#include <memory>

#include "continuum/integrator.hpp"

namespace grainscale::continuum {

class ArkodeImex final : public TimeIntegrator {
 public:
  ArkodeImex(const Model& model, IntegratorSettings settings);
  ~ArkodeImex() override;
  ArkodeImex(const ArkodeImex&) = delete;
  ArkodeImex& operator=(const ArkodeImex&) = delete;

  void advance(double t0, double t1, std::vector<double>& state) override;
  void restart() override { needs_init_ = true; }
  std::string name() const override { return "arkode_imex"; }
  IntegratorStats stats() const override;

 private:
  struct Sundials;
  const Model& model_;
  IntegratorSettings settings_;
  std::unique_ptr<Sundials> s_;
  bool needs_init_ = true;
  double t_current_ = 0;
};

}  // namespace grainscale::continuum
