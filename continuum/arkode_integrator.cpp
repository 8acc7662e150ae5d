#include "continuum/arkode_integrator.hpp"

#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
#include "continuum/sundials_band_system.hpp"
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>

#include <algorithm>
#include <span>
#include <stdexcept>
#include <string>

namespace grainscale::continuum {

namespace {

int rhs_part(realtype t, N_Vector y, N_Vector ydot, void* user, TermPart part) {
  const auto* model = static_cast<const Model*>(user);
  const auto n = static_cast<std::size_t>(N_VGetLength(y));
  model->state_rhs(t, std::span<const double>(N_VGetArrayPointer(y), n), std::span<double>(N_VGetArrayPointer(ydot), n),
                   part);
  return 0;
}

int explicit_rhs(realtype t, N_Vector y, N_Vector ydot, void* user) { return rhs_part(t, y, ydot, user, TermPart::explicit_part); }
int implicit_rhs(realtype t, N_Vector y, N_Vector ydot, void* user) { return rhs_part(t, y, ydot, user, TermPart::implicit_part); }

int implicit_jacobian(realtype t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector, N_Vector) {
  fill_band_jacobian(*static_cast<const Model*>(user), t, y, J, TermPart::implicit_part);
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("ARKODE: ") + what + " failed with flag " + std::to_string(flag));
}

}  // namespace

struct ArkodeImex::Sundials {
  SundialsBandSystem band;  // freed after the integrator memory (member order)
  void* ark = nullptr;
  explicit Sundials(const Model& model) : band(model, "ARKODE") {}
  ~Sundials() {
    if (ark) ARKStepFree(&ark);
  }
};

ArkodeImex::ArkodeImex(const Model& model, IntegratorSettings settings)
    : model_(model), settings_(std::move(settings)), s_(std::make_unique<Sundials>(model)) {
  s_->ark = ARKStepCreate(explicit_rhs, implicit_rhs, 0.0, s_->band.y, s_->band.ctx);
  if (!s_->ark) throw std::runtime_error("ARKODE: allocation failed");
  check(ARKStepSetUserData(s_->ark, const_cast<Model*>(&model_)), "ARKStepSetUserData");
  check(s_->band.set_scaled_abstol(model_, settings_.atol, [&](N_Vector abstol) { return ARKStepSVtolerances(s_->ark, settings_.rtol, abstol); }),
        "ARKStepSVtolerances");
  check(ARKStepSetLinearSolver(s_->ark, s_->band.solver, s_->band.jac), "ARKStepSetLinearSolver");
  check(ARKStepSetJacFn(s_->ark, implicit_jacobian), "ARKStepSetJacFn");
  // As for CVODE (cvode_integrator.cpp): unscaled Newton corrections keep the linear invariant.
  check(ARKStepSetLinearSolutionScaling(s_->ark, SUNFALSE), "ARKStepSetLinearSolutionScaling");
  check(ARKStepSetMaxNumSteps(s_->ark, settings_.max_steps), "ARKStepSetMaxNumSteps");
  if (settings_.max_dt > 0) check(ARKStepSetMaxStep(s_->ark, settings_.max_dt), "ARKStepSetMaxStep");
}

ArkodeImex::~ArkodeImex() = default;

void ArkodeImex::advance(double t0, double t1, std::vector<double>& c) {
  if (c.size() != model_.state_size()) {
    throw std::invalid_argument("arkode_imex: the vector has " + std::to_string(c.size()) + " entries, the model's state " +
                                std::to_string(model_.state_size()) + " (advance Model::state(t, c))");
  }
  if (t1 <= t0) return;
  double* y = N_VGetArrayPointer(s_->band.y);
  if (!needs_init_ && (t0 != t_current_ || !std::equal(c.begin(), c.end(), y))) needs_init_ = true;
  if (needs_init_) {
    std::copy(c.begin(), c.end(), y);
    check(ARKStepReInit(s_->ark, explicit_rhs, implicit_rhs, t0, s_->band.y), "ARKStepReInit");
    needs_init_ = false;
  }
  check(ARKStepSetStopTime(s_->ark, t1), "ARKStepSetStopTime");
  double t_reached = t0;
  check(ARKStepEvolve(s_->ark, t1, s_->band.y, &t_reached, ARK_NORMAL), "ARKStepEvolve");
  std::copy(y, y + c.size(), c.begin());
  t_current_ = t_reached;
}

IntegratorStats ArkodeImex::stats() const {
  IntegratorStats st;
  long v = 0;
  ARKStepGetNumSteps(s_->ark, &v);
  st.steps = v;
  long fe = 0, fi = 0;
  ARKStepGetNumRhsEvals(s_->ark, &fe, &fi);
  st.rhs_evaluations = fe + fi;
  ARKStepGetNumJacEvals(s_->ark, &v);
  st.jacobian_evaluations = v;
  return st;
}

}  // namespace grainscale::continuum
