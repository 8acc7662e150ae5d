#pragma once
// What both implicit SUNDIALS integrators (cvode_integrator, arkode_integrator) set up the same way:
// a context, the state vector, a band matrix of the model's half-bandwidth and its direct band
// solver (RAII), plus the two things they do alike with them - absolute tolerances scaled to the
// state's entries, and the band Jacobian filled from Model::state_jacobian.
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <functional>

#include "continuum/model.hpp"

namespace grainscale::continuum {

struct SundialsBandSystem {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr;
  SUNMatrix jac = nullptr;
  SUNLinearSolver solver = nullptr;

  /// Throws std::runtime_error naming `who` (e.g. "CVODE") if an allocation fails.
  SundialsBandSystem(const Model& model, const char* who);
  ~SundialsBandSystem();
  SundialsBandSystem(const SundialsBandSystem&) = delete;
  SundialsBandSystem& operator=(const SundialsBandSystem&) = delete;

  /// atol is on c; the state's entries carry c times an area or depth (Model::state_scale), so the
  /// per-entry tolerance is atol * scale. `set` receives the vector (e.g. CVodeSVtolerances) and
  /// its flag is returned; the vector is freed afterwards.
  int set_scaled_abstol(const Model& model, double atol, const std::function<int(N_Vector)>& set) const;
};

/// J := d(rhs)/dy of `part` at (t, y), a band matrix (exact column sums: conservative_jacobian.hpp).
void fill_band_jacobian(const Model& model, double t, N_Vector y, SUNMatrix J, TermPart part = TermPart::all);

}  // namespace grainscale::continuum
