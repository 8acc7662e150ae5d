#pragma once
// Closed-form flows for verification and synthetic studies.
#include <functional>

#include "continuum/flow.hpp"

namespace grainscale::continuum {

/// No bulk motion and a uniform shear rate: the "uniform shear layer" of the steady
/// segregation–diffusion test (vertical motion is absent, only γ̇ drives segregation and mixing).
class UniformShear final : public Flow {
 public:
  explicit UniformShear(double shear_rate) : rate_(shear_rate) {}
  double stream_function(double, double, double) const override { return 0; }
  double shear_rate(double, double, double) const override { return rate_; }
  bool steady() const override { return true; }

 private:
  double rate_;
};

/// One convection cell in a bed of depth h(x): ψ = A sin(π x / L) sin(π z / h(x)) (ψ = 0 on walls,
/// floor and surface), plus γ̇ = |∂u/∂z + ∂w/∂x| + γ̇₀ for a flat bed (γ̇₀ a background rate).
/// `surface` gives h(x); pass the grid's piecewise-linear surface for exact zero surface flux.
class CellularFlow final : public Flow {
 public:
  CellularFlow(double amplitude, double length, std::function<double(double)> surface, double background_shear = 0);
  double stream_function(double x, double z, double t) const override;
  /// Shear rate of the flat-bed cell (uses h at x); a smooth, positive field for the coefficients.
  double shear_rate(double x, double z, double t) const override;
  bool steady() const override { return true; }

 private:
  double amplitude_, length_;
  std::function<double(double)> surface_;
  double background_;
};

/// Any flow given by two functions (manufactured-solution tests, time-dependent forcing).
class FunctionFlow final : public Flow {
 public:
  using Field = std::function<double(double, double, double)>;
  FunctionFlow(Field psi, Field shear_rate, bool steady) : psi_(std::move(psi)), rate_(std::move(shear_rate)), steady_(steady) {}
  double stream_function(double x, double z, double t) const override { return psi_(x, z, t); }
  double shear_rate(double x, double z, double t) const override { return rate_(x, z, t); }
  bool steady() const override { return steady_; }

 private:
  Field psi_, rate_;
  bool steady_;
};

}  // namespace grainscale::continuum
