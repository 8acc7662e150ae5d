#include "continuum/integrator.hpp"

#include "continuum/arkode_integrator.hpp"
#include "continuum/cvode_integrator.hpp"
#include "continuum/ssp_rk3.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

const std::vector<std::string>& integrator_names() {
  static const std::vector<std::string> names{"cvode", "ssp_rk3", "arkode_imex"};
  return names;
}

std::unique_ptr<TimeIntegrator> make_integrator(const IntegratorSettings& s, const Model& model) {
  if (s.method == "cvode") return std::make_unique<CvodeIntegrator>(model, s);
  if (s.method == "ssp_rk3") return std::make_unique<SspRk3>(model, s);
  if (s.method == "arkode_imex") return std::make_unique<ArkodeImex>(model, s);
  throw InputError("unknown integrator '" + s.method + "'; choose cvode, ssp_rk3 or arkode_imex");
}

}  // namespace grainscale::continuum
