#pragma once
// What a photograph of the bed from above sees: the fraction of the surface covered by chaff,
//   coverage(x) = 1 − exp(−κ ∫_{h−δ}^{h} c dz),                                      (O1)
// a Beer–Lambert-like saturation of the chaff volume per unit area in a top layer of thickness δ.
// κ [1/m] (visible area of chaff per unit chaff volume, including overlap) is fitted; δ [m], the
// depth that can be seen into (about one grain diameter), is set.
#include <span>
#include <vector>

#include "continuum/grid.hpp"
#include "continuum/parameter.hpp"

namespace grainscale::continuum {

class SurfaceCoverage {
 public:
  SurfaceCoverage(double kappa, double delta);
  ParameterSet& parameters() { return params_; }
  const ParameterSet& parameters() const { return params_; }

  /// ∫_{h−δ}^{h} c dz per column [m], from the cells overlapping the top layer.
  std::vector<double> top_layer_content(const Grid& grid, std::span<const double> c) const;
  /// (O1) per column.
  std::vector<double> coverage(const Grid& grid, std::span<const double> c) const;

 private:
  ParameterSet params_;
};

}  // namespace grainscale::continuum
