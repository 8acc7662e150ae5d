#include "continuum/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
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
  const auto* model = static_cast<const Model*>(user);
  const auto n = static_cast<std::size_t>(N_VGetLength(y));
  SUNMatZero(J);
  const int b = static_cast<int>(SUNBandMatrix_UpperBandwidth(J));
  model->state_jacobian(t, std::span<const double>(N_VGetArrayPointer(y), n), b,
                        [&](std::size_t row, std::size_t col, double v) {
                               SM_ELEMENT_B(J, static_cast<sunindextype>(row), static_cast<sunindextype>(col)) += v;
                             });
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed with flag " + std::to_string(flag));
}

}  // namespace

struct CvodeIntegrator::Sundials {
  SUNContext ctx = nullptr;
  N_Vector y = nullptr;
  SUNMatrix jac = nullptr;
  SUNLinearSolver solver = nullptr;
  void* cvode = nullptr;
  ~Sundials() {
    if (cvode) CVodeFree(&cvode);
    if (solver) SUNLinSolFree(solver);
    if (jac) SUNMatDestroy(jac);
    if (y) N_VDestroy(y);
    if (ctx) SUNContext_Free(&ctx);
  }
};

CvodeIntegrator::CvodeIntegrator(const Model& model, IntegratorSettings settings)
    : model_(model), settings_(std::move(settings)), s_(std::make_unique<Sundials>()) {
  const auto n = static_cast<sunindextype>(model.state_size());
  const auto bw = static_cast<sunindextype>(model.state_half_bandwidth());
  check(SUNContext_Create(nullptr, &s_->ctx), "SUNContext_Create");
  s_->y = N_VNew_Serial(n, s_->ctx);
  N_VConst(0.0, s_->y);
  s_->jac = SUNBandMatrix(n, bw, bw, s_->ctx);
  s_->solver = SUNLinSol_Band(s_->y, s_->jac, s_->ctx);
  s_->cvode = CVodeCreate(CV_BDF, s_->ctx);
  if (!s_->y || !s_->jac || !s_->solver || !s_->cvode) throw std::runtime_error("CVODE: allocation failed");
  check(CVodeInit(s_->cvode, rhs_callback, 0.0, s_->y), "CVodeInit");
  check(CVodeSetUserData(s_->cvode, const_cast<Model*>(&model_)), "CVodeSetUserData");
  {
    // atol is on c; the state's entries carry c times an area or depth (Model::state_scale).
    N_Vector abstol = N_VClone(s_->y);
    const std::vector<double> scale = model_.state_scale();
    for (std::size_t j = 0; j < scale.size(); ++j) N_VGetArrayPointer(abstol)[j] = settings_.atol * scale[j];
    const int flag = CVodeSVtolerances(s_->cvode, settings_.rtol, abstol);
    N_VDestroy(abstol);
    check(flag, "CVodeSVtolerances");
  }
  check(CVodeSetLinearSolver(s_->cvode, s_->solver, s_->jac), "CVodeSetLinearSolver");
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
  double* y = N_VGetArrayPointer(s_->y);
  // Continue the history only if this call picks up where the last one stopped with the same state.
  if (!needs_init_ && (t0 != t_current_ || !std::equal(c.begin(), c.end(), y))) needs_init_ = true;
  if (needs_init_) {
    std::copy(c.begin(), c.end(), y);
    check(CVodeReInit(s_->cvode, t0, s_->y), "CVodeReInit");
    needs_init_ = false;
  }
  check(CVodeSetStopTime(s_->cvode, t1), "CVodeSetStopTime");
  double t_reached = t0;
  check(CVode(s_->cvode, t1, s_->y, &t_reached, CV_NORMAL), "CVode");
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
