#pragma once
// Time integration of the semi-discrete model (model.hpp) behind one interface, so SUNDIALS and the
// home-made integrator can be swapped and cross-checked (tests/continuum/test_integrators.cpp).
#include <memory>
#include <string>
#include <vector>

#include "continuum/model.hpp"

namespace grainscale::continuum {

struct IntegratorSettings {
  std::string method = "cvode";  // "cvode" (BDF, band Jacobian), "ssp_rk3" (explicit) or "arkode_imex"
  double rtol = 1e-6;            // cvode, arkode_imex: relative tolerance
  double atol = 1e-9;            // cvode, arkode_imex: absolute tolerance on the state
  double cfl = 0.4;              // ssp_rk3: dt = cfl / max_rate
  double max_dt = 0;             // both: upper bound on the step, 0 = none
  long max_steps = 1000000;      // per advance() call
};

struct IntegratorStats {
  long steps = 0;
  long rhs_evaluations = 0;
  long jacobian_evaluations = 0;  // cvode only
};

class TimeIntegrator {
 public:
  virtual ~TimeIntegrator() = default;
  /// Advance the model's state (Model::state(); c itself for a fixed surface) from t0 to t1. t1 is a
  /// stop time: no step passes it, so the forcing may change there.
  virtual void advance(double t0, double t1, std::vector<double>& state) = 0;
  /// The forcing jumps at the current time (a pause or switch of the motion): forget the history.
  virtual void restart() = 0;
  virtual std::string name() const = 0;
  virtual IntegratorStats stats() const = 0;
};

const std::vector<std::string>& integrator_names();
/// The integrator keeps a reference to `model`, which must outlive it.
std::unique_ptr<TimeIntegrator> make_integrator(const IntegratorSettings& settings, const Model& model);

}  // namespace grainscale::continuum
