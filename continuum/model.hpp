#pragma once
// The semi-discrete model: on each cell (i, k) of area A,
//   A dc/dt = −Σ_faces F_face(c) + A s(x, z, t),                                   (M1)
// F the sum of the registered flux terms (flux_term.hpp) and s an optional source (manufactured
// solutions only). Boundary faces carry no flux, so Σ A c changes only through s.
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "continuum/face_coefficients.hpp"
#include "continuum/flow.hpp"
#include "continuum/flux_term.hpp"
#include "continuum/grid.hpp"

namespace grainscale::continuum {

class Model {
 public:
  Model(Grid grid, std::shared_ptr<const Flow> flow);

  void add_term(std::unique_ptr<FluxTerm> term);
  /// Source s(x, z, t) [1/s], evaluated at cell centres (manufactured-solution tests).
  void set_source(std::function<double(double, double, double)> source) {
    source_ = std::move(source);
    source_valid_ = false;
  }

  const Grid& grid() const { return grid_; }
  const Flow& flow() const { return *flow_; }
  std::size_t size() const { return grid_.cells(); }
  bool has_term(const std::string& name) const;
  FluxTerm& term(const std::string& name);
  const FluxTerm& term(const std::string& name) const;

  /// Parameters addressed as "term.parameter", e.g. "segregation.S".
  std::vector<std::string> parameter_names() const;
  double parameter(const std::string& qualified) const;
  void set_parameter(const std::string& qualified, double value);

  /// Σ over terms of the face fluxes at (t, c) (no source).
  void face_fluxes(double t, std::span<const double> c, FaceFluxes& out) const;
  /// dc/dt from (M1).
  void rhs(double t, std::span<const double> c, std::span<double> dcdt) const;
  /// Largest Σ_terms rate bound over the cells [1/s]; an explicit step needs dt · this ≤ CFL.
  double max_rate(double t) const;
  /// Half-width of the Jacobian band over all terms.
  int jacobian_half_bandwidth() const;
  /// Chaff per unit width, Σ A c [m²].
  double chaff(std::span<const double> c) const;
  /// Face fluxes of the last rhs() call (diagnostics).
  const FaceFluxes& last_fluxes() const { return fluxes_; }

 private:
  void update_faces(double t) const;

  Grid grid_;
  std::shared_ptr<const Flow> flow_;
  std::vector<std::unique_ptr<FluxTerm>> terms_;
  std::function<double(double, double, double)> source_;
  mutable FaceCoefficients faces_;
  mutable double faces_time_;
  mutable bool faces_valid_ = false;
  mutable FaceFluxes fluxes_;
  // The source does not depend on c: cached per time, so CVODE's difference-quotient Jacobian
  // (many rhs calls at one t) evaluates it once.
  mutable std::vector<double> source_values_;
  mutable double source_time_ = 0;
  mutable bool source_valid_ = false;
};

}  // namespace grainscale::continuum
