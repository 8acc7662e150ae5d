#pragma once
// SUNDIALS CVODE, variable-order BDF with Newton iterations and a band direct solver. The band
// Jacobian comes from difference quotients of the face fluxes (conservative_jacobian.hpp), so its
// area-weighted column sums vanish; with CVODE's rescaling of Newton corrections switched off,
// every Newton iterate then has the predicted total chaff, and BDF keeps the total to round-off.
// Unlike SSP-RK3, BDF does not guarantee c in [0, 1]: excursions are of the order of the tolerances.
#include <memory>

#include "continuum/integrator.hpp"

namespace grainscale::continuum {

class CvodeIntegrator final : public TimeIntegrator {
 public:
  CvodeIntegrator(const Model& model, IntegratorSettings settings);
  ~CvodeIntegrator() override;
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  void advance(double t0, double t1, std::vector<double>& c) override;
  void restart() override { needs_init_ = true; }
  std::string name() const override { return "cvode"; }
  IntegratorStats stats() const override;

 private:
  struct Sundials;  // SUNContext, vector, matrix, solver, CVODE memory (RAII in the .cpp)
  const Model& model_;
  IntegratorSettings settings_;
  std::unique_ptr<Sundials> s_;
  bool needs_init_ = true;
  double t_current_ = 0;
};

}  // namespace grainscale::continuum
