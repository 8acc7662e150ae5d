#pragma once
// What a hold prediction reports, from the chaff field on the window grid (flat top window of
// depth W; z = W is the grain surface):
//  - surface concentration: c in the top cell of each column (what the top layer holds);
//  - end fractions: the share of all modelled chaff that lies in the top `top_layer` metres within
//    `end_zone` metres of each end wall (the report's "chaff in the right-hand 100 mm", at hold scale);
//  - spear profile: the mean c a grain spear (probe) of length L_s pushed down from the surface at x
//    collects, c_spear(x) = (1/L_s) ∫_{W−L_s}^{W} c dz, the part below the window at the background
//    concentration (no flow reaches there); "dirty" where c_spear > factor × the initial mean.
#include <utility>
#include <vector>

#include "continuum/grid.hpp"

namespace grainscale::studies {

std::vector<double> surface_concentration(const continuum::Grid& g, const std::vector<double>& c);
/// (left, right) fractions of Σ A c.
std::pair<double, double> end_top_fractions(const continuum::Grid& g, const std::vector<double>& c, double top_layer,
                                            double end_zone);
std::vector<double> spear_profile(const continuum::Grid& g, const std::vector<double>& c, double spear_depth,
                                  double background);

}  // namespace grainscale::studies
