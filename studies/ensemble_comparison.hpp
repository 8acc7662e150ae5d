#pragma once
// The comparison an ensemble study reports: each measure's mean, sd and n per variant over the
// seeds, and each variant's difference from the reference variant with its Welch interval
// (studies/welch_interval.hpp). The chaff field (relative chaff concentration per slice at the end)
// is compared as one number: the RMS of the per-slice differences of the variants' mean profiles
// over the RMS of their standard errors,
//
//   ratio = sqrt(mean_k d_k^2) / sqrt(mean_k se_k^2),  se_k^2 = s_a,k^2 / n_a + s_b,k^2 / n_b,
//
// which is about 1 when two variants differ only by seed scatter. It is called a difference when
// ratio^2 exceeds chi^2_{p}(K) / K (K slices; the normal approximation: with few seeds the standard
// errors are themselves uncertain, so this is a screening threshold, not an exact test), and the
// number of slices whose own Welch interval excludes zero is reported beside it.
#include <string>
#include <vector>

#include "studies/ensemble_run.hpp"
#include "studies/welch_interval.hpp"

namespace grainscale::studies {

struct MeasureComparison {
  std::string key, label, unit;
  std::vector<SampleStats> per_variant;    // in settings order
  std::vector<WelchInterval> vs_reference; // per variant (the reference's own entry: zero difference)
};

struct FieldComparison {
  std::vector<double> slice_lo, slice_hi;
  std::vector<std::vector<SampleStats>> per_variant;  // [variant][slice]
  std::vector<double> rms_difference, rms_error, ratio, threshold;  // per variant vs the reference
  std::vector<int> slices_differing;                 // per variant
  std::vector<bool> differs;
};

struct EnsembleComparison {
  std::size_t reference = 0;  // index of the reference variant
  std::vector<MeasureComparison> measures;
  FieldComparison field;                                   // relative chaff per slice at the end
  std::vector<std::vector<SampleStats>> percent_start, percent_end;  // [variant][slice], chaff % per slice
};

/// Measures compared: index_end (congregation index at the end), index_change (end - start),
/// bulk_density, bed_height, surface_speed, and aor (when the study runs the AOR test).
EnsembleComparison compare_variants(const EnsembleSettings& s, const EnsembleResults& r);

/// The runs of one variant, in seed order.
std::vector<const EnsembleRunRecord*> runs_of(const EnsembleResults& r, const std::string& variant);

}  // namespace grainscale::studies
