#pragma once
// SUNDIALS CVODE, variable-order BDF with Newton iterations and a band direct solver. The band
// Jacobian is built by CVODE's grouped difference quotients over the model's band half-width
// (model.hpp), which is exact in structure because the band covers the whole stencil. BDF with an
// exact-structure Jacobian keeps linear invariants, so total chaff is conserved to round-off
// (up to the linear solve), but unlike SSP-RK3 it does not guarantee c in [0, 1]: overshoots are
// of the order of the tolerances.
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
