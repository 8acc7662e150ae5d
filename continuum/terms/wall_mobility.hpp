#pragma once
// Wall-proximity mobility. Next to the end walls the grain slides along the wall (wall friction is
// lower than internal friction, and the walls move with the container), so chaff there is more
// mobile than the width-averaged γ̇ of the interior says; chaff climbs the walls and collects in the
// corners (the report's photographs show it along the end walls). As an extra upward drift that
// decays away from the walls over a few grain diameters,
//   v_z = W exp(−min(x, L − x) / ℓ_w)                                               (WM1)
// carried as q c (1 − c) (drift_flux.hpp) through σ-faces. W [m/s] is fitted; ℓ_w [m] is set.
#include "continuum/drift_flux.hpp"

namespace grainscale::continuum {

class WallMobility final : public FluxTerm {
 public:
  explicit WallMobility(Limiter limiter);
  void add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const override;
  void add_rate_bound(const TermContext& ctx, std::span<double> rate) const override;
  int jacobian_half_bandwidth(const Grid& grid) const override;

 private:
  DriftField field(const TermContext& ctx) const;
  const DriftCache& faces_q(const TermContext& ctx) const;
  Limiter limiter_;
  mutable FaceStates states_;
  mutable DriftCache cache_;
};

}  // namespace grainscale::continuum
