#pragma once
// Slices along the container's length, the way the source report binned its DEM results: "the
// simulation space was split into approx. 50mm slices and the particles counted for each slice"
// (SAGIT USA120 report, Figure 11: chaff particles per slice as a percentage of all chaff particles,
// initial and final).
#include <vector>

namespace grainscale::cg {

/// Slices of `width` from x_lo to x_hi; the last one is narrower if the length is not a multiple of
/// the width (a remainder below 1e-9 of a width is dropped, so 0.8 m / 0.05 m gives 16 slices).
struct Slices {
  double x_lo = 0, x_hi = 0, width = 0;

  Slices(double x_lo, double x_hi, double width);
  int count() const { return n_; }
  double lower(int s) const { return x_lo + s * width; }
  double upper(int s) const { return s + 1 == n_ ? x_hi : x_lo + (s + 1) * width; }
  double centre(int s) const { return 0.5 * (lower(s) + upper(s)); }
  /// Slice of coordinate x; -1 outside [x_lo, x_hi] (x_hi itself belongs to the last slice).
  int of(double x) const;

 private:
  int n_ = 0;
};

}  // namespace grainscale::cg
