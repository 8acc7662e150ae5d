#include "continuum/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include "continuum/sundials_band_system.hpp"
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>

#include <algorithm>

#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

namespace grainscale::continuum {

namespace {

int rhs_callback(realtype t, N_Vector y, N_Vector ydot, void* user) {
  const auto* model = static_cast<const Model*>(user);
  const auto n = static_cast<std::size_t>(N_VGetLength(y));
  model->state_rhs(t, std::span<const double>(N_VGetArrayPointer(y), n), std::span<double>(N_VGetArrayPointer(ydot), n));
  return 0;
}

/// Band Jacobian with exact column sums (conservative_jacobian.hpp).
int jacobian_callback(realtype t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector, N_Vector) {
  fill_band_jacobian(*static_cast<const Model*>(user), t, y, J);
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed with flag " + std::to_string(flag));
}

}  // namespace

struct CvodeIntegrator::Sundials {
  SundialsBandSystem band;  // freed after the integrator memory (member order)
  void* cvode = nullptr;
  explicit Sundials(const Model& model) : band(model, "CVODE") {}
  ~Sundials() {
    if (cvode) CVodeFree(&cvode);
  }
};

CvodeIntegrator::CvodeIntegrator(const Model& model, IntegratorSettings settings)
    : model_(model), settings_(std::move(settings)), s_(std::make_unique<Sundials>(model)) {
  s_->cvode = CVodeCreate(CV_BDF, s_->band.ctx);
  if (!s_->cvode) throw std::runtime_error("CVODE: allocation failed");
  check(CVodeInit(s_->cvode, rhs_callback, 0.0, s_->band.y), "CVodeInit");
  check(CVodeSetUserData(s_->cvode, const_cast<Model*>(&model_)), "CVodeSetUserData");
  check(s_->band.set_scaled_abstol(model_, settings_.atol, [&](N_Vector abstol) { return CVodeSVtolerances(s_->cvode, settings_.rtol, abstol); }),
        "CVodeSVtolerances");
  check(CVodeSetLinearSolver(s_->cvode, s_->band.solver, s_->band.jac), "CVodeSetLinearSolver");
  // Keep total chaff: with Σ A_i J_ij = 0 every Newton correction δ = −(I − γJ)⁻¹ G moves the
  // total exactly to its predicted value. CVODE's default rescaling of δ by 2 / (1 + γ/γ_old)
  // (after γ changed since the last Jacobian) would break that and leave an O(tolerance) drift.
  check(CVodeSetLinearSolutionScaling(s_->cvode, SUNFALSE), "CVodeSetLinearSolutionScaling");
  check(CVodeSetJacFn(s_->cvode, jacobian_callback), "CVodeSetJacFn");
  check(CVodeSetMaxNumSteps(s_->cvode, settings_.max_steps), "CVodeSetMaxNumSteps");
  if (settings_.max_dt > 0) check(CVodeSetMaxStep(s_->cvode, settings_.max_dt), "CVodeSetMaxStep");
}

CvodeIntegrator::~CvodeIntegrator() = default;

void CvodeIntegrator::advance(double t0, double t1, std::vector<double>& c) {
  if (c.size() != model_.state_size()) {
    throw std::invalid_argument("cvode: the vector has " + std::to_string(c.size()) + " entries, the model's state " +
                                std::to_string(model_.state_size()) + " (advance Model::state(t, c), not c, for a moving " +
                                "surface or the depth-averaged model)");
  }
  if (t1 <= t0) return;
  double* y = N_VGetArrayPointer(s_->band.y);
  // Continue the history only if this call picks up where the last one stopped with the same state.
  if (!needs_init_ && (t0 != t_current_ || !std::equal(c.begin(), c.end(), y))) needs_init_ = true;
  if (needs_init_) {
    std::copy(c.begin(), c.end(), y);
    check(CVodeReInit(s_->cvode, t0, s_->band.y), "CVodeReInit");
    needs_init_ = false;
  }
  check(CVodeSetStopTime(s_->cvode, t1), "CVodeSetStopTime");
  double t_reached = t0;
  check(CVode(s_->cvode, t1, s_->band.y, &t_reached, CV_NORMAL), "CVode");
  std::copy(y, y + c.size(), c.begin());
  t_current_ = t_reached;
}

IntegratorStats CvodeIntegrator::stats() const {
  IntegratorStats st;
  long v = 0;
  CVodeGetNumSteps(s_->cvode, &v);
  st.steps = v;
  CVodeGetNumRhsEvals(s_->cvode, &v);
  st.rhs_evaluations = v;
  long lsrhs = 0;
  CVodeGetNumLinRhsEvals(s_->cvode, &lsrhs);  // difference-quotient Jacobian evaluations of f
  st.rhs_evaluations += lsrhs;
  CVodeGetNumJacEvals(s_->cvode, &v);
  st.jacobian_evaluations = v;
  return st;
}

}  // namespace grainscale::continuum
