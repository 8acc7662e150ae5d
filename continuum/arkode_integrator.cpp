#include "continuum/arkode_integrator.hpp"

#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
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
  const auto* model = static_cast<const Model*>(user);
  const auto n = static_cast<std::size_t>(N_VGetLength(y));
  SUNMatZero(J);
  const int b = static_cast<int>(SUNBandMatrix_UpperBandwidth(J));
  model->state_jacobian(
      t, std::span<const double>(N_VGetArrayPointer(y), n), b,
      [&](std::size_t row, std::size_t col, double v) {
        SM_ELEMENT_B(J, static_cast<sunindextype>(row), static_cast<sunindextype>(col)) += v;
      },
      TermPart::implicit_part);
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("ARKODE: ") + what + " failed with flag " + std::to_string(flag));
}

}  // namespace

struct ArkodeImex::Sundials {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr;
  SUNMatrix jac = nullptr;
  SUNLinearSolver solver = nullptr;
  void* ark = nullptr;
  ~Sundials() {
    if (ark) ARKStepFree(&ark);
    if (solver) SUNLinSolFree(solver);
    if (jac) SUNMatDestroy(jac);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }
};

ArkodeImex::ArkodeImex(const Model& model, IntegratorSettings settings)
    : model_(model), settings_(std::move(settings)), s_(std::make_unique<Sundials>()) {
  const auto n = static_cast<sunindextype>(model.state_size());
  const auto bw = static_cast<sunindextype>(model.state_half_bandwidth());
  check(SUNContext_Create(nullptr, &s_->ctx), "SUNContext_Create");
  s_->y = N_VNew_Serial(n, s_->ctx);
  N_VConst(0.0, s_->y);
  s_->jac = SUNBandMatrix(n, bw, bw, s_->ctx);
  s_->solver = SUNLinSol_Band(s_->y, s_->jac, s_->ctx);
  s_->ark = ARKStepCreate(explicit_rhs, implicit_rhs, 0.0, s_->y, s_->ctx);
  if (!s_->y || !s_->jac || !s_->solver || !s_->ark) throw std::runtime_error("ARKODE: allocation failed");
  check(ARKStepSetUserData(s_->ark, const_cast<Model*>(&model_)), "ARKStepSetUserData");
  {
    // atol is on c; the state's entries carry c times an area or depth (Model::state_scale).
    N_Vector abstol = N_VClone(s_->y);
    const std::vector<double> scale = model_.state_scale();
    for (std::size_t j = 0; j < scale.size(); ++j) N_VGetArrayPointer(abstol)[j] = settings_.atol * scale[j];
    const int flag = ARKStepSVtolerances(s_->ark, settings_.rtol, abstol);
    N_VDestroy(abstol);
    check(flag, "ARKStepSVtolerances");
  }
  check(ARKStepSetLinearSolver(s_->ark, s_->solver, s_->jac), "ARKStepSetLinearSolver");
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
  double* y = N_VGetArrayPointer(s_->y);
  if (!needs_init_ && (t0 != t_current_ || !std::equal(c.begin(), c.end(), y))) needs_init_ = true;
  if (needs_init_) {
    std::copy(c.begin(), c.end(), y);
    check(ARKStepReInit(s_->ark, explicit_rhs, implicit_rhs, t0, s_->y), "ARKStepReInit");
    needs_init_ = false;
  }
  check(ARKStepSetStopTime(s_->ark, t1), "ARKStepSetStopTime");
  double t_reached = t0;
  check(ARKStepEvolve(s_->ark, t1, s_->y, &t_reached, ARK_NORMAL), "ARKStepEvolve");
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
