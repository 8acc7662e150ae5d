#include "continuum/integrator.hpp"

#include "continuum/cvode_integrator.hpp"
#include "continuum/ssp_rk3.hpp"
#include "dem/input_error.hpp"

namespace grainscale::continuum {

const std::vector<std::string>& integrator_names() {
  static const std::vector<std::string> names{"cvode", "ssp_rk3"};
  return names;
}

std::unique_ptr<TimeIntegrator> make_integrator(const IntegratorSettings& s, const Model& model) {
  if (s.method == "cvode") return std::make_unique<CvodeIntegrator>(model, s);
  if (s.method == "ssp_rk3") return std::make_unique<SspRk3>(model, s);
  throw InputError("unknown integrator '" + s.method + "'; choose cvode or ssp_rk3");
}

}  // namespace grainscale::continuum
