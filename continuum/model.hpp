#pragma once
// The semi-discrete model: on each cell (i, k) of area A,
//   d(A c)/dt = −Σ_faces F_face(c) + A s(x, z, t),                                  (M1)
// F the sum of the registered flux terms (flux_term.hpp) and s an optional source (manufactured
// solutions only). Boundary faces carry no flux, so Σ A c changes only through s.
//
// What the time integrator integrates (the *state* y) depends on the formulation:
// - fixed surface: y = c (A constant, so (M1) is A dc/dt = ...);
// - moving surface (flow.moving_surface()): y = (A c of each cell, column area a_i) interleaved per
//   column, y[i (nz+1) + k] = A_ik c_ik, y[i (nz+1) + nz] = a_i, with A_ik = dσ a_i and
//     d(A c)/dt = −Σ_faces F(c; Q_rel),   da_i/dt = q_i − q_{i+1}                    (M2)
//   (face_coefficients.hpp, F1). Σ y over the chaff entries is the total chaff and a linear
//   invariant, so every integrator keeps it to round-off; a and A c are advanced by the same
//   formula, so a uniform c stays uniform to round-off with SSP-RK3 (geometric conservation law).
// - depth-averaged closure (depth_averaged.hpp): y = chaff inventory I_i = ∫ c dz per column.
// Integrators use only the state_* functions; c on the grid comes back through concentration().
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

class DepthAveraged;

/// Which terms an evaluation includes: all of them, or the explicit / implicit part of an IMEX split
/// (FluxTerm::implicit_in_imex; the source and the column-area rates are explicit).
enum class TermPart { all, explicit_part, implicit_part };

enum class Closure {
  resolved,        // the 2-D model (M1)/(M2)
  depth_averaged   // the 1-D variant (depth_averaged.hpp)
};

class Model {
 public:
  Model(Grid grid, std::shared_ptr<const Flow> flow, Closure closure = Closure::resolved);
  ~Model();
  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;

  void add_term(std::unique_ptr<FluxTerm> term);
  /// Depth-averaged closure only: average its face fluxes over `phases` times of the motion period
  /// (depth_averaged.hpp); phases = 0 switches it off.
  void set_cycle_average(double period, int phases);
  /// Source s(x, z, t) [1/s], evaluated at cell centres (manufactured-solution tests).
  void set_source(std::function<double(double, double, double)> source) {
    source_ = std::move(source);
    source_valid_ = false;
  }

  /// The grid at the start (for a moving surface: the surface the model was built with).
  const Grid& grid() const { return grid_; }
  const Flow& flow() const { return *flow_; }
  Closure closure() const { return closure_; }
  bool moving_surface() const { return flow_->moving_surface(); }
  /// Number of cells of the grid (size of c).
  std::size_t size() const { return grid_.cells(); }
  bool has_term(const std::string& name) const;
  FluxTerm& term(const std::string& name);
  const FluxTerm& term(const std::string& name) const;
  std::vector<const FluxTerm*> terms() const;

  /// Parameters addressed as "term.parameter", e.g. "segregation.S".
  std::vector<std::string> parameter_names() const;
  double parameter(const std::string& qualified) const;
  void set_parameter(const std::string& qualified, double value);

  // ---- the 2-D equations on a fixed grid (c as unknown); for a moving surface on the grid of the
  // last state evaluated.
  /// Σ over terms of the face fluxes at (t, c) (no source).
  void face_fluxes(double t, std::span<const double> c, FaceFluxes& out, TermPart part = TermPart::all) const;
  /// dc/dt from (M1) (fixed surface).
  void rhs(double t, std::span<const double> c, std::span<double> dcdt) const;
  /// Largest Σ_terms rate bound over the cells [1/s]; an explicit step needs dt · this ≤ CFL (for
  /// the depth-averaged closure: its own bound).
  double max_rate(double t) const;
  /// Half-width of the Jacobian band over all terms (index of c).
  int jacobian_half_bandwidth() const;
  /// Chaff per unit width, Σ A c [m²], on the starting grid.
  double chaff(std::span<const double> c) const;
  /// Face fluxes of the last rhs() call (diagnostics).
  const FaceFluxes& last_fluxes() const { return fluxes_; }

  // ---- the state the integrators advance (see the header comment).
  std::size_t state_size() const;
  /// State from c on the grid at time t (the surface at t; for the depth-averaged closure the
  /// column inventories Σ_k c dσ h̄).
  std::vector<double> state(double t, std::span<const double> c) const;
  /// c on the grid of state y at time t.
  std::vector<double> concentration(double t, std::span<const double> y) const;
  /// The grid of state y at time t (nodes h(x_f, t), column depths a_i / dx for a moving surface).
  Grid grid_of(double t, std::span<const double> y) const;
  /// The grid with the surface at time t and trapezoid depths (the starting grid if it does not move).
  Grid surface_grid(double t) const;
  /// Total chaff of a state [m²] (a linear invariant of the state).
  double state_chaff(std::span<const double> y) const;
  void state_rhs(double t, std::span<const double> y, std::span<double> dydt, TermPart part = TermPart::all) const;
  double state_max_rate(double t, std::span<const double> y) const;
  int state_half_bandwidth() const;
  /// Size of a unit of c in each state entry, on the starting grid (1 for c; the cell area for A c;
  /// the column area for a; the depth for I): an absolute tolerance on c times this is one on y.
  std::vector<double> state_scale() const;
  /// ∂(dy/dt)/∂y inside the band |row − col| ≤ b, with Σ_rows (chaff weight) J = 0 to round-off.
  void state_jacobian(double t, std::span<const double> y, int b,
                      const std::function<void(std::size_t, std::size_t, double)>& add, TermPart part = TermPart::all) const;

 private:
  void update_faces(double t) const;
  void set_geometry(double t, std::span<const double> y) const;  // moving surface: current_ from y
  void evaluate_source(double t, const Grid& g) const;

  Grid grid_;
  std::shared_ptr<const Flow> flow_;
  Closure closure_;
  std::vector<std::unique_ptr<FluxTerm>> terms_;
  std::function<double(double, double, double)> source_;
  mutable Grid current_;  // grid of the current evaluation (== grid_ for a fixed surface)
  mutable FaceCoefficients faces_;
  mutable double faces_time_ = 0;
  mutable bool faces_valid_ = false;
  mutable FaceFluxes fluxes_;
  mutable std::vector<double> c_scratch_;
  // The source does not depend on c: cached per time, so CVODE's difference-quotient Jacobian
  // (many rhs calls at one t) evaluates it once.
  mutable std::vector<double> source_values_;
  mutable double source_time_ = 0;
  mutable bool source_valid_ = false;
  std::unique_ptr<DepthAveraged> depth_averaged_;
};

}  // namespace grainscale::continuum
