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

/// A sloshing standing wave with a moving free surface (verification of the moving σ-grid, and
/// synthetic studies of a tilting box):
///   h(x, t) = H + a cos(k x) sin(ω t),  k = n π / L,  ω = 2π / T,
///   q(x, t) = −(a ω / k) sin(k x) cos(ω t)       (∂h/∂t + ∂q/∂x = 0, q = 0 at the walls),
///   ψ(x, z, t) = q(x, t) (z / h)^p + A sin(π x / L) sin(π z / h),
/// i.e. the sloshing bulk flux spread over the depth with the profile u ∝ σ^(p−1) (p = 1: plug flow,
/// p = 2: linear shear), plus an optional convection cell that does not cross the surface.
/// γ̇ = |∂u/∂z| of the sloshing part (flat-bed estimate, p (p−1) |q| σ^(p−2) / h²) + γ̇₀.
class SloshingFlow final : public Flow {
 public:
  struct Shape {
    double length = 0.4, depth = 0.1;  // L, H [m]
    double amplitude = 0.01;           // a [m], < H
    int mode = 1;                      // n
    double period = 2.0;               // T [s]
    double exponent = 2;               // p ≥ 1
    double cell = 0;                   // A [m²/s]
    double background_shear = 0;       // γ̇₀ [1/s]
  };
  explicit SloshingFlow(Shape shape);
  double stream_function(double x, double z, double t) const override;
  double shear_rate(double x, double z, double t) const override;
  bool steady() const override { return false; }
  bool moving_surface() const override { return true; }
  double surface_height(double x, double t) const override;
  /// q(x, t) = ψ at the surface.
  double surface_flux(double x, double t) const;
  const Shape& shape() const { return shape_; }

 private:
  Shape shape_;
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
