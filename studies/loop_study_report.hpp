#pragma once
// report.md of a `kind: loop` study (docs/studies.md): the story of one `grainscale loop` run told to a
// reader without the code - what was run with its wall clock, the data and their provenance and
// caveats, the base fit, the residual diagnosis, the ranked candidate effects, the effect added (or
// why none), the error before and after (RMSE, max, cross-validated), the figures the loop drew
// (embedded from loop/), and the limits, worked out from the numbers (observations per parameter,
// observation times, usable cross-validation folds). loop/report.md keeps the loop's full tables.
#include <string>

#include "studies/loop_study.hpp"

namespace grainscale::studies {

/// Writes `folder`/report.md atomically; returns its path.
std::string write_loop_study_report(const LoopStudySettings& s, const LoopStudyResults& r, const std::string& folder);

}  // namespace grainscale::studies
