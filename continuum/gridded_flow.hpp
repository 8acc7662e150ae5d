#pragma once
// Bulk flow from coarse-grained DEM fields on a regular (x, z) grid, in the container frame and
// averaged over the width (docs/continuum.md, "Field input"). Only the horizontal velocity u and
// γ̇ are used: the vertical velocity is rebuilt from continuity through the stream function
//   ψ(x, z) = ∫₀ᶻ [u(x, z') − Q(x)/h(x)] dz',   Q(x) = ∫₀^{h(x)} u dz,                (G1)
// which vanishes on the floor and on the surface. Subtracting the depth mean Q/h (zero for an exact,
// steady, closed bed) removes the net column flux that noise and phase averaging leave, which would
// otherwise be a source or sink of bulk at the surface. Between data columns ψ is interpolated at
// equal σ = z/h, and it tapers linearly to zero at the end walls x = 0 and x = L.
#include <string>
#include <utility>
#include <vector>

#include "continuum/flow.hpp"

namespace grainscale::continuum {

class GriddedFlow final : public Flow {
 public:
  /// Read the HDF5 layout of docs/continuum.md, or a coarse-graining field file (fields.h5 of
  /// `grainscale cg`, 2-D grid; `frame` selects the frame, negative counts from the end); `length`
  /// is the bed length L (walls at 0 and L). `temperature_diameter` d > 0 (coarse-graining files
  /// only): the rate returned as shear_rate() is sqrt(T) / d from the mixture's granular temperature
  /// T instead of the mean flow's γ̇. Kinetic theory's diffusivity d sqrt(T) is then the dense
  /// rheology's γ̇ d² with γ̇ → sqrt(T)/d (Savage & Dai, Mech. Mater. 16 (1993) 225): agitation that
  /// the cycle-mean flow does not see (a bed shaken back and forth) still mixes and segregates.
  /// `volume_flux` (coarse-graining files only): the stream function integrates the solids' volume
  /// flux φ u (scaled by the column's mean φ below its surface) instead of u, so the dilute surface
  /// cells' fast, nearly massless flow does not enter it, nor the depth-mean correction (G1) that
  /// would spread its return flow over the dense bed.
  static GriddedFlow load(const std::string& file, double length, int frame = -1, double temperature_diameter = 0,
                          bool volume_flux = false);
  GriddedFlow(double length, std::vector<double> x, std::vector<double> z, std::vector<double> u,
              std::vector<double> shear_rate, std::vector<double> surface_height);

  double stream_function(double x, double z, double t) const override;
  double shear_rate(double x, double z, double t) const override;
  bool steady() const override { return true; }
  /// h(x), linear between data columns, constant beyond the first and last.
  double surface_height(double x) const;
  /// ∫₀ˣ h dx′ [m²] of that piecewise-linear surface (exact).
  double surface_integral(double x) const;
  /// The same fields under a surface scaled by `factor` (phase_resolved_flow.hpp equalises the bed
  /// area of the phases this way).
  GriddedFlow with_surface_scaled(double factor) const;
  double length() const { return length_; }

  /// Frames of a coarse-graining field file that are phase averages (finite `phase_lo`, `phase_hi`
  /// and at least one snapshot): frame index and bin centre in cycles, in file order.
  static std::vector<std::pair<int, double>> phase_frames(const std::string& file);

 private:
  double column_psi(int j, double sigma) const;  // (G1) on data column j at σ
  double length_;
  std::vector<double> x_, z_, u_, rate_, h_;     // u_, rate_ stored [z][x]
  std::vector<std::vector<double>> psi_sigma_;   // per column: ψ at σ_m = m / (S − 1)
};

}  // namespace grainscale::continuum
