#include "continuum/analytic_flows.hpp"

#include <cmath>
#include <numbers>

namespace grainscale::continuum {

CellularFlow::CellularFlow(double amplitude, double length, std::function<double(double)> surface,
                           double background_shear)
    : amplitude_(amplitude), length_(length), surface_(std::move(surface)), background_(background_shear) {}

double CellularFlow::stream_function(double x, double z, double) const {
  constexpr double pi = std::numbers::pi;
  return amplitude_ * std::sin(pi * x / length_) * std::sin(pi * z / surface_(x));
}

double CellularFlow::shear_rate(double x, double z, double) const {
  // Flat-bed cell: u = A (π/h) sin(πx/L) cos(πz/h), w = −A (π/L) cos(πx/L) sin(πz/h);
  // ∂u/∂z + ∂w/∂x = −A π² (1/h² − 1/L²) sin(πx/L) sin(πz/h).
  constexpr double pi = std::numbers::pi;
  const double h = surface_(x);
  const double s = amplitude_ * pi * pi * (1 / (h * h) - 1 / (length_ * length_)) * std::sin(pi * x / length_) *
                   std::sin(pi * z / h);
  return std::abs(s) + background_;
}

}  // namespace grainscale::continuum
