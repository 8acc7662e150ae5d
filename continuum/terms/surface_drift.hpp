#pragma once
// Surface-layer drift of floating chaff to the flow front. Each half-cycle the top of the tilted bed
// flows downhill as a thin surface avalanche; flat, light chaff rides on top of it, reaches the
// front (the downhill end wall) and is left there when the flow stops, while the grain that carried
// it is recirculated through the bulk (the report: chaff "pushed upward and to the end of the
// container"; photographs: ~60 % coverage at the ends, ~10 % in the centre). Averaged over a
// symmetric cycle this is a drift towards both ends, confined to the surface layer:
//   v_x = U sin(π (x − L/2) / L) · [z > h − δ_s]                                     (SD1)
// carried as q c (1 − c) (drift_flux.hpp): only chaff moves relative to the grain. U [m/s] is
// fitted; δ_s [m], the thickness of the flowing layer (a few grain diameters), is set.
// Only x-faces carry it; a face partly inside the layer carries the overlapping part.
#include "continuum/drift_flux.hpp"

namespace grainscale::continuum {

class SurfaceDrift final : public FluxTerm {
 public:
  explicit SurfaceDrift(Limiter limiter);
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
