#pragma once
// The study's report.md (read without the code: what was run, figures, numbers, comparison with the
// report's measurements and what limits the comparison) and the prediction's figures.
#include <string>

#include "studies/numeric_csv.hpp"
#include "studies/study_run.hpp"

namespace grainscale::studies {

/// Writes `out/report.md` atomically; returns its path.
std::string write_study_report(const StudySettings& s, const StudyResults& r, const std::string& out);

/// From the continuum's coverage.csv (time_s, then one column per column centre x): coverage along x
/// at every output time (coverage.png) and the centre/end-zone coverage over time (coverage_time.png)
/// with the report's measured 10 % / 60 %.
void write_prediction_figures(const NumericCsv& coverage, const std::string& folder, double end_length);

}  // namespace grainscale::studies
