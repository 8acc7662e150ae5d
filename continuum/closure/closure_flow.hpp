#pragma once
// The flow closure as the chaff model's flow (continuum/flow.hpp): from the recorded surface speed
// u_s(x, t) (flow_record.hpp) and the profile (S0) of shallow_granular_flow.hpp, over a chaff grid
// whose column depth is H(x) (the grid's own surface; H may be a top window of a deep bed):
//
//   u(x, z, t) = u_s e^{−ζ/ℓ},  ζ = H − z (depth below the surface)
//   ψ_raw     = ∫₀ᶻ u dz′ = u_s ℓ (e^{−ζ/ℓ} − e^{−H/ℓ}),   Q = ψ_raw(z = H) = u_s ℓ (1 − e^{−H/ℓ})   (P1)
//   γ̇         = |∂u/∂z| = |u_s| e^{−ζ/ℓ} / ℓ                                                     (P2)
//
// Two modes:
//  - frozen surface (the grid keeps its initial surface): ψ = ψ_raw − (z/H) Q, so ψ = 0 on floor
//    and surface and no chaff crosses them. The net column flux Q — the part that moves the surface
//    — is replaced by a uniform return flow Q/H (the same choice as gridded_flow.hpp's (G1) for DEM
//    fields). In a deep bed (H ≫ ℓ) the return flow is slow and the surface layer is carried at
//    nearly u_s; the chaff map is right where the surface moves little.
//  - moving surface: ψ = ψ_raw, H = h(x, t) from the record; the surface flux Q equals the closure's
//    mass flux, so ∂h/∂t = −∂Q/∂x is the kinematic condition a moving grid must satisfy. It needs
//    a grid that follows h(x, t) (the moving-surface grid of issue 7).
// ℓ = ∞ (plug flow) gives γ̇ = 0 and, frozen, ψ = 0 (the bed moves as a block).
// Not thread-safe: it caches the record interpolated at the last t asked for (face coefficients are
// evaluated column by column at one t).
#include <functional>
#include <memory>

#include "continuum/closure/flow_record.hpp"
#include "continuum/flow.hpp"

namespace grainscale::continuum::closure {

class ClosureFlow final : public Flow {
 public:
  /// `grid_surface`: H(x) of the chaff grid (frozen mode); ignored in moving mode.
  ClosureFlow(std::shared_ptr<const FlowRecord> record, double layer_depth, std::function<double(double)> grid_surface,
              bool moving = false);
  double stream_function(double x, double z, double t) const override;
  double shear_rate(double x, double z, double t) const override;
  /// Steady when the record holds one sample (a cycle average).
  bool steady() const override { return record_->samples().size() == 1; }
  bool moving_surface() const override { return moving_; }
  /// h(x, t) of the closure, linear between cell centres.
  double surface_height(double x, double t) const override;
  /// u_s(x, t), linear between faces.
  double surface_speed(double x, double t) const;

 private:
  void refresh(double t) const;
  double face_value(const std::vector<double>& v, double x) const;
  double column_depth(double x, double t) const;

  std::shared_ptr<const FlowRecord> record_;
  double ell_;
  std::function<double(double)> surface_;
  bool moving_;
  mutable FlowSample cache_;
  mutable double cache_t_ = 0;
  mutable const FlowSample* cache_of_ = nullptr;  // record sample data the cache was built from
  mutable std::size_t cache_count_ = 0;
  mutable bool cached_ = false;
};

}  // namespace grainscale::continuum::closure
