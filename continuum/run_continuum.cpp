#include "continuum/run_continuum.hpp"

#include <algorithm>
#include <filesystem>

#include "continuum/field_output.hpp"
#include "continuum/simulate.hpp"
#include "dem/atomic_file.hpp"

namespace grainscale::continuum {

ContinuumRunSummary run_continuum(const ContinuumSettings& s) {
  const Model model = build_model(s);
  const SurfaceCoverage camera(s.kappa, s.delta);
  const std::vector<double> c0 = initial_field(s, model.grid());

  RunRecord record;
  record.times = output_times(s);
  std::vector<Grid> grids;
  record.fields = simulate(model, c0, 0.0, record.times, s.integrator, s.stops, &grids);
  record.times.insert(record.times.begin(), 0.0);
  // The depth-averaged closure starts from the equilibrium profile of the initial inventories.
  record.fields.insert(record.fields.begin(), model.concentration(0.0, model.state(0.0, c0)));
  if (model.moving_surface()) {
    grids.insert(grids.begin(), model.grid());
    record.grids = std::move(grids);
  }

  std::filesystem::create_directories(s.output_folder);
  ContinuumRunSummary summary;
  summary.h5_file = s.output_folder + "/continuum.h5";
  summary.slices_file = s.output_folder + "/slices.csv";
  summary.coverage_file = s.output_folder + "/coverage.csv";
  write_continuum_h5(summary.h5_file, model, camera, record);
  dem::write_file_atomically(summary.slices_file, slices_csv(model, record, s.slice_width));
  dem::write_file_atomically(summary.coverage_file, coverage_csv(model, camera, record));

  summary.chaff_initial = record.grid(model, 0).integrate(record.fields.front());
  summary.chaff_final = record.grid(model, record.times.size() - 1).integrate(record.fields.back());
  summary.c_min = 1;
  summary.c_max = 0;
  for (const auto& c : record.fields) {
    summary.c_min = std::min(summary.c_min, *std::min_element(c.begin(), c.end()));
    summary.c_max = std::max(summary.c_max, *std::max_element(c.begin(), c.end()));
  }
  return summary;
}

}  // namespace grainscale::continuum
