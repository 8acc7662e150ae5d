#pragma once
// The chaff sandwich: a 2x wheat grain landing on a 2x chaff flake on the perspex floor, the case
// where the Rayleigh rule's step is not stable (docs/contact_models.md). Used by the stability
// check's tests (test_clumps.cpp) and the step control's (test_step_control.cpp).
#include <algorithm>
#include <memory>

#include "dem/shape.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/plane.hpp"

namespace grainscale::dem::testing {

struct Landing {
  double flake_speed = 0;  // largest speed of the chaff flake, m/s
  double overlap = 0;      // largest overlap / radius
  StepStability worst;     // worst per-body step stability seen
  double lowest_dt = 0;    // the smallest step taken, s
  double dt_ceiling = 0;   // the step the input set, s
};

/// The report's chaff (100 kg/m^3, G = 1 MPa) at 2x size is a 5.6 mg flake; a 0.4 g wheat grain
/// lands on it at 2.4 m/s and squeezes it against the floor, nine contacts on one light body.
/// 0.02 s at `fraction` of the Rayleigh time, the stability checked every `stability_interval` steps.
inline Landing land_on_chaff(double fraction, StepControl control = {}, int stability_interval = 1) {
  const MaterialTable mt = MaterialTable::load(GRAINSCALE_SOURCE_DIR "/studies/materials/report_table1.yaml");
  SimulationSettings st;
  st.time_step_fraction = fraction;
  st.max_overlap_ratio = 0.99;
  st.stability_interval = stability_interval;
  st.step_control = control;
  Simulation sim(mt, st);
  Shape wheat = load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/wheat.yaml");
  Shape chaff = load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/chaff.yaml");
  for (Shape* s : {&wheat, &chaff})
    for (auto& c : s->spheres) c.center = 2.0 * c.center, c.radius *= 2;
  sim.add_clump(chaff, mt.index("chaff"), 100, {0, 0, 0.0015});
  sim.add_clump(wheat, mt.index("barley"), 1380, {0.001, 0.0005, 0.0065}, axis_angle({0, 0, 1}, 0.7), {0, 0, -2.4});
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), mt.index("perspex"));
  sim.setup();
  Landing r;
  while (sim.time() < 0.02 - 0.5 * sim.dt() && r.flake_speed < 5) {
    sim.step();
    r.flake_speed = std::max(r.flake_speed, norm(sim.bodies().v[sim.bodies().index_of(0)]));
    r.overlap = std::max(r.overlap, sim.diagnostics().max_overlap_ratio);
  }
  r.worst = sim.worst_stability();
  r.lowest_dt = sim.lowest_dt();
  r.dt_ceiling = sim.dt_ceiling();
  return r;
}

}  // namespace grainscale::dem::testing
