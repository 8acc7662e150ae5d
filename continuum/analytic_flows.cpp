#include "continuum/analytic_flows.hpp"

#include <algorithm>
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

SloshingFlow::SloshingFlow(Shape s) : shape_(s) {}

double SloshingFlow::surface_height(double x, double t) const {
  constexpr double pi = std::numbers::pi;
  const double k = shape_.mode * pi / shape_.length, w = 2 * pi / shape_.period;
  return shape_.depth + shape_.amplitude * std::cos(k * x) * std::sin(w * t);
}

double SloshingFlow::surface_flux(double x, double t) const {
  constexpr double pi = std::numbers::pi;
  const double k = shape_.mode * pi / shape_.length, w = 2 * pi / shape_.period;
  return -shape_.amplitude * w / k * std::sin(k * x) * std::cos(w * t);
}

double SloshingFlow::stream_function(double x, double z, double t) const {
  constexpr double pi = std::numbers::pi;
  const double h = surface_height(x, t);
  const double sigma = z / h;
  double psi = surface_flux(x, t) * std::pow(std::max(sigma, 0.0), shape_.exponent);
  if (shape_.cell != 0) psi += shape_.cell * std::sin(pi * x / shape_.length) * std::sin(pi * sigma);
  return psi;
}

double SloshingFlow::shear_rate(double x, double z, double t) const {
  const double h = surface_height(x, t), p = shape_.exponent;
  const double sigma = std::clamp(z / h, 0.0, 1.0);
  const double dudz = p > 1 ? p * (p - 1) * std::abs(surface_flux(x, t)) * std::pow(sigma, p - 2) / (h * h) : 0.0;
  return dudz + shape_.background_shear;
}

}  // namespace grainscale::continuum
