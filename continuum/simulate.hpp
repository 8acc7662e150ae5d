#pragma once
// Run the model from c0 at t0 through a list of output times; the forward map of the fit and of
// the driver. `stops` are extra times where the forcing jumps (motion pauses, switches): the
// integrator stops exactly there and restarts its history. The integrator advances the model's state
// (model.hpp); c0 and the results are concentrations on the grid.
#include <vector>

#include "continuum/integrator.hpp"
#include "continuum/model.hpp"

namespace grainscale::continuum {

/// c at each of `times` (increasing, > t0), on the grid at that time: with a moving surface the grid
/// changes, and `grids` (if given) receives it per output time (Model::grid_of).
std::vector<std::vector<double>> simulate(const Model& model, std::vector<double> c0, double t0,
                                          const std::vector<double>& times, const IntegratorSettings& settings,
                                          const std::vector<double>& stops = {}, std::vector<Grid>* grids = nullptr);

}  // namespace grainscale::continuum
