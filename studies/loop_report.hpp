#pragma once
// The outputs of `grainscale loop` (docs/loop.md): loop.yaml (numbers), report.md (the story: base
// fit, diagnosis, ranking, the effect chosen and why, its strength, error before and after) and the
// figures: diagnosis (regions, harmonics, residual vs the model's c, autocorrelation), ranking, and
// data / model / residual before and after (the `grainscale fit` figures, fit_plots.hpp).
#include <string>
#include <vector>

#include "continuum/grid.hpp"

namespace grainscale::studies {

struct LoopSettings;
struct LoopResult;
struct FitCommandSettings;

/// Write everything into settings.output_folder; returns the paths written.
std::vector<std::string> write_loop_outputs(const LoopSettings& settings, const FitCommandSettings& fit,
                                            const continuum::Grid& grid, const LoopResult& result);

}  // namespace grainscale::studies
