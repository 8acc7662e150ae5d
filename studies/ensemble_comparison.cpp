#include "studies/ensemble_comparison.hpp"

#include <gsl/gsl_cdf.h>

#include <cmath>
#include <functional>
#include <limits>

namespace grainscale::studies {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Per-slice statistics of one profile over a variant's runs.
std::vector<SampleStats> profile_stats(const std::vector<const EnsembleRunRecord*>& runs,
                                       const std::function<const std::vector<double>&(const RunMeasures&)>& of,
                                       std::size_t slices) {
  std::vector<SampleStats> out(slices);
  for (std::size_t k = 0; k < slices; ++k) {
    std::vector<double> v;
    for (const EnsembleRunRecord* r : runs) {
      const std::vector<double>& p = of(r->measures);
      v.push_back(k < p.size() ? p[k] : kNaN);
    }
    out[k] = sample_stats(v);
  }
  return out;
}

}  // namespace

std::vector<const EnsembleRunRecord*> runs_of(const EnsembleResults& r, const std::string& variant) {
  std::vector<const EnsembleRunRecord*> out;
  for (const auto& run : r.runs) {
    if (run.variant == variant) out.push_back(&run);
  }
  return out;
}

EnsembleComparison compare_variants(const EnsembleSettings& s, const EnsembleResults& r) {
  EnsembleComparison c;
  for (std::size_t v = 0; v < s.variants.size(); ++v) {
    if (s.variants[v].name == s.reference) c.reference = v;
  }
  struct Def {
    const char *key, *label, *unit;
    std::function<double(const EnsembleRunRecord&)> of;
  };
  std::vector<Def> defs = {
      {"index_end", "congregation index at the end (mean of the compartments' end indices)", "-",
       [](const EnsembleRunRecord& x) { return x.measures.index_end; }},
      {"index_change", "change of that index during the motion (end - start)", "-",
       [](const EnsembleRunRecord& x) { return x.measures.index_end - x.measures.index_start; }},
      {"bulk_density", "bulk density of the settled bed", "kg/m^3",
       [](const EnsembleRunRecord& x) { return x.measures.bulk_density; }},
      {"bed_height", "mean bed height at the motion start", "m",
       [](const EnsembleRunRecord& x) { return x.measures.bed_height; }},
      {"surface_speed", "surface-flow speed during the motion (relative to the box)", "m/s",
       [](const EnsembleRunRecord& x) { return x.measures.surface_speed; }},
  };
  if (s.aor) {
    defs.push_back({"aor", "angle of repose (AOR rig at the variant's scale)", "deg",
                    [](const EnsembleRunRecord& x) { return x.aor_deg; }});
  }
  for (const Def& d : defs) {
    MeasureComparison m{d.key, d.label, d.unit, {}, {}};
    for (const EnsembleVariant& v : s.variants) {
      std::vector<double> values;
      for (const EnsembleRunRecord* run : runs_of(r, v.name)) values.push_back(d.of(*run));
      m.per_variant.push_back(sample_stats(values));
    }
    for (const SampleStats& st : m.per_variant) m.vs_reference.push_back(welch_interval(m.per_variant[c.reference], st, s.confidence));
    c.measures.push_back(m);
  }

  // Profiles per slice.
  std::size_t slices = 0;
  for (const auto& run : r.runs) {
    if (run.measures.slice_lo.size() > slices) {
      slices = run.measures.slice_lo.size();
      c.field.slice_lo = run.measures.slice_lo;
      c.field.slice_hi = run.measures.slice_hi;
    }
  }
  for (const EnsembleVariant& v : s.variants) {
    const auto runs = runs_of(r, v.name);
    c.field.per_variant.push_back(profile_stats(runs, [](const RunMeasures& m) -> const std::vector<double>& { return m.relative_chaff_end; }, slices));
    c.percent_start.push_back(profile_stats(runs, [](const RunMeasures& m) -> const std::vector<double>& { return m.chaff_percent_start; }, slices));
    c.percent_end.push_back(profile_stats(runs, [](const RunMeasures& m) -> const std::vector<double>& { return m.chaff_percent_end; }, slices));
  }
  FieldComparison& f = c.field;
  for (std::size_t v = 0; v < s.variants.size(); ++v) {
    double d2 = 0, e2 = 0;
    int k_used = 0, differing = 0;
    for (std::size_t k = 0; k < slices; ++k) {
      const WelchInterval w = welch_interval(f.per_variant[c.reference][k], f.per_variant[v][k], s.confidence);
      if (!w.defined) continue;
      d2 += w.difference * w.difference;
      e2 += w.standard_error * w.standard_error;
      ++k_used;
      if (w.excludes_zero) ++differing;
    }
    const double rms_d = k_used ? std::sqrt(d2 / k_used) : kNaN, rms_e = k_used ? std::sqrt(e2 / k_used) : kNaN;
    const double ratio = rms_e > 0 ? rms_d / rms_e : (rms_d > 0 ? INFINITY : kNaN);
    const double threshold = k_used ? std::sqrt(gsl_cdf_chisq_Pinv(s.confidence, k_used) / k_used) : kNaN;
    f.rms_difference.push_back(rms_d);
    f.rms_error.push_back(rms_e);
    f.ratio.push_back(ratio);
    f.threshold.push_back(threshold);
    f.slices_differing.push_back(differing);
    f.differs.push_back(v != c.reference && std::isfinite(threshold) && ratio > threshold);
  }
  return c;
}

}  // namespace grainscale::studies
