#include "continuum/simulate.hpp"

#include <algorithm>
#include <stdexcept>

namespace grainscale::continuum {

std::vector<std::vector<double>> simulate(const Model& model, std::vector<double> c, double t0,
                                          const std::vector<double>& times, const IntegratorSettings& settings,
                                          const std::vector<double>& stops, std::vector<Grid>* grids) {
  auto integrator = make_integrator(settings, model);
  if (grids) grids->clear();
  std::vector<double> y = model.state(t0, c);
  std::vector<std::vector<double>> out;
  out.reserve(times.size());
  double t = t0;
  std::size_t next_stop = 0;
  std::vector<double> sorted_stops = stops;
  std::sort(sorted_stops.begin(), sorted_stops.end());
  for (double target : times) {
    if (target < t) throw std::invalid_argument("simulate: output times must increase from t0");
    // Stop at every forcing jump before the target, then restart the integrator's history there.
    while (next_stop < sorted_stops.size() && sorted_stops[next_stop] <= target) {
      const double s = sorted_stops[next_stop++];
      if (s <= t) continue;
      integrator->advance(t, s, y);
      t = s;
      integrator->restart();
    }
    integrator->advance(t, target, y);
    t = target;
    out.push_back(model.concentration(t, y));
    if (grids) grids->push_back(model.grid_of(t, y));
  }
  return out;
}

}  // namespace grainscale::continuum
