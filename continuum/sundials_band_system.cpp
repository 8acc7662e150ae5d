#include "continuum/sundials_band_system.hpp"

#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>

#include <span>
#include <stdexcept>
#include <string>

namespace grainscale::continuum {

SundialsBandSystem::SundialsBandSystem(const Model& model, const char* who) {
  const auto n = static_cast<sunindextype>(model.state_size());
  const auto bw = static_cast<sunindextype>(model.state_half_bandwidth());
  if (SUNContext_Create(nullptr, &ctx) < 0) throw std::runtime_error(std::string(who) + ": SUNContext_Create failed");
  y = N_VNew_Serial(n, ctx);
  if (y) N_VConst(0.0, y);
  jac = SUNBandMatrix(n, bw, bw, ctx);
  if (y && jac) solver = SUNLinSol_Band(y, jac, ctx);
  if (!y || !jac || !solver) throw std::runtime_error(std::string(who) + ": allocation failed");
}

SundialsBandSystem::~SundialsBandSystem() {
  if (solver) SUNLinSolFree(solver);
  if (jac) SUNMatDestroy(jac);
  if (y) N_VDestroy(y);
  if (ctx) SUNContext_Free(&ctx);
}

int SundialsBandSystem::set_scaled_abstol(const Model& model, double atol, const std::function<int(N_Vector)>& set) const {
  N_Vector abstol = N_VClone(y);
  const std::vector<double> scale = model.state_scale();
  for (std::size_t j = 0; j < scale.size(); ++j) N_VGetArrayPointer(abstol)[j] = atol * scale[j];
  const int flag = set(abstol);
  N_VDestroy(abstol);
  return flag;
}

void fill_band_jacobian(const Model& model, double t, N_Vector y, SUNMatrix J, TermPart part) {
  const auto n = static_cast<std::size_t>(N_VGetLength(y));
  SUNMatZero(J);
  const int b = static_cast<int>(SUNBandMatrix_UpperBandwidth(J));
  model.state_jacobian(
      t, std::span<const double>(N_VGetArrayPointer(y), n), b,
      [&](std::size_t row, std::size_t col, double v) {
        SM_ELEMENT_B(J, static_cast<sunindextype>(row), static_cast<sunindextype>(col)) += v;
      },
      part);
}

}  // namespace grainscale::continuum
