#pragma once
// What an ensemble study writes beside its runs (docs/studies.md, "Ensemble studies"):
//   report.md        what was run (per run: status, size, wall clock), warnings, the measures per run,
//                    per variant over seeds, the differences from the reference with their intervals,
//                    the chaff per slice (figures), the comparison with the source report, the
//                    verdict, the limits
//   runs.csv         one row per run: every measure (per compartment too)
//   slices.csv       one row per run and slice: chaff % at the start and the end, relative chaff
//   slices_end.png, slices_<variant>.png, relative_chaff.png, index.png
// and, in each run's folder, measures.csv (write_run_measures).
#include <string>

#include "studies/ensemble_run.hpp"

namespace grainscale::studies {

/// One run's measures as `key,value` rows (per compartment: compartment_<k>_<what>).
void write_run_measures(const std::string& file, const EnsembleRunRecord& r);

/// Writes the report, the CSV tables and the figures into `out`; returns the report's path.
std::string write_ensemble_report(const EnsembleSettings& s, const EnsembleResults& r, const std::string& out);

}  // namespace grainscale::studies
