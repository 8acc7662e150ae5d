#pragma once
// Files of a hold prediction (docs/hold_prediction.md, "Output"), all written atomically beside
// their PNG figures: continuum.h5 (c on the window grid, format of docs/continuum.md),
// surface_chaff.csv/.png, end_fractions.csv/.png, spear.csv/.png, surface.csv/.png (closure h),
// chaff_map.png (final c), summary.yaml.
#include <string>
#include <vector>

#include "studies/hold_run.hpp"

namespace grainscale::studies {

struct HoldFiles {
  std::string folder;
  std::vector<std::string> written;
  std::vector<double> dirty_from, dirty_to;  // x intervals where a spear finds dirty grain at the end [m]
  double left_fraction = 0, right_fraction = 0;  // end fractions at the end
};

HoldFiles write_hold_output(const HoldSettings& s, const HoldModel& model, const HoldResult& r);

}  // namespace grainscale::studies
