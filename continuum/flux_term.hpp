#pragma once
// One continuum effect = one flux term. A term adds its flux through every interior face; the model
// sums the terms and takes the divergence cell by cell (model.cpp). Boundary faces (walls, floor,
// free surface) are never written, which is the zero-normal-flux condition and makes the total
// amount of chaff a telescoping sum, conserved to round-off whatever the terms do.
//
// To add an effect: write continuum/terms/<name>.{hpp,cpp} deriving from FluxTerm, and add one
// line to term_registry.cpp.
#include <span>
#include <string>
#include <vector>

#include "continuum/face_coefficients.hpp"
#include "continuum/grid.hpp"
#include "continuum/parameter.hpp"

namespace grainscale::continuum {

/// Fluxes of chaff volume (per unit width) through the faces [m²/s], numbered as in face_coefficients.hpp.
struct FaceFluxes {
  std::vector<double> x;  // +x through x-faces
  std::vector<double> s;  // upward through σ-faces
  void reset(const Grid& g) {
    x.assign(x_face_count(g), 0.0);
    s.assign(s_face_count(g), 0.0);
  }
};

/// What a term may read: the grid and the flow on the faces at the current time.
struct TermContext {
  const Grid& grid;
  const FaceCoefficients& faces;
};

class FluxTerm {
 public:
  FluxTerm(std::string name, std::vector<Parameter> params) : name_(name), params_(std::move(name), std::move(params)) {}
  virtual ~FluxTerm() = default;

  const std::string& name() const { return name_; }
  ParameterSet& parameters() { return params_; }
  const ParameterSet& parameters() const { return params_; }

  /// Add this term's flux through every interior face.
  virtual void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const = 0;
  /// Add, per cell, a bound on Σ_faces |∂(flux)/∂c| / area [1/s]: the explicit step must satisfy
  /// dt · Σ_terms bound ≤ CFL (ssp_rk3.cpp).
  virtual void add_rate_bound(const TermContext& ctx, std::span<double> rate) const = 0;
  /// Half-width of the band of ∂(dc/dt)/∂c this term produces (index = i·nz + k).
  virtual int jacobian_half_bandwidth(const Grid& grid) const = 0;
  /// True for the stiff, diffusive terms an IMEX integrator treats implicitly (arkode_integrator.hpp);
  /// the others are explicit there.
  virtual bool implicit_in_imex() const { return false; }

 private:
  std::string name_;
  ParameterSet params_;
};

}  // namespace grainscale::continuum
