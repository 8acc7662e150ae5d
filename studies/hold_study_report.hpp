#pragma once
// report.md of a `kind: hold` study (docs/studies.md): what was run and its wall clock, warnings, the
// scenarios ranked by predicted congregation, each scenario's chaff build-up near the end walls over
// time with its spear result and figures, the cost of a simulated day against issue 8's 10 minutes,
// the comparison with the report's photographs for the report's box, the closure against
// coarse-grained DEM (if asked), and the limits.
#include <string>

#include "studies/hold_study.hpp"

namespace grainscale::studies {

/// Writes `folder`/report.md atomically; returns its path.
std::string write_hold_study_report(const HoldStudySettings& s, const HoldStudyResults& r, const std::string& folder);

/// The report's measured top-view coverage after 30 min (centre about 10 %, ends about 60 %;
/// ../shared/data/source_measurements.yaml) turned into the ratio of chaff in the visible top layer,
/// end / centre, through the coverage operator (O1), coverage = 1 - exp(-κ∫c): ln(1 - 0.6) / ln(1 - 0.1).
/// Independent of κ.
double report_visible_chaff_ratio();

}  // namespace grainscale::studies
