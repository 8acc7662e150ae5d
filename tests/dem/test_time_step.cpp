// The automatic time step is a fraction of the Rayleigh time (Li, Xu & Thornton 2005).
#include <catch2/catch.hpp>

#include "dem/simulation.hpp"
#include "dem/time_step.hpp"

using namespace grainscale::dem;
using Catch::Matchers::WithinRel;

TEST_CASE("Rayleigh time of the report's barley at 2x size", "[dem][timestep]") {
  const Material barley{"barley", 1380, 2.6e6, 0.3};
  // pi * 6.7e-3 * sqrt(1380 / 2.6e6) / (0.1631 * 0.3 + 0.8766) = 0.0210487 * 0.0230384 / 0.92553
  CHECK_THAT(rayleigh_time(6.7e-3, barley), WithinRel(5.23947e-4, 1e-5));
}

TEST_CASE("The simulation takes its step from the smallest, softest particle unless told otherwise",
          "[dem][timestep]") {
  MaterialTable mt;
  mt.add({"stiff", 2500, 1e9, 0.25});
  mt.add({"soft", 100, 1e6, 0.4});
  mt.set_pair(0, 0, {0.5, 0.5, 0, true});
  mt.set_pair(0, 1, {0.5, 0.5, 0, true});
  mt.set_pair(1, 1, {0.5, 0.5, 0, true});
  SimulationSettings st;
  st.gravity = {};
  Simulation sim(mt, st);
  sim.add_sphere(0, 0.002, {0, 0, 0});
  sim.add_sphere(1, 0.005, {0.1, 0, 0});
  sim.setup();
  const double expect = 0.2 * std::min(rayleigh_time(0.002, mt[0]), rayleigh_time(0.005, mt[1]));
  CHECK_THAT(sim.dt(), WithinRel(expect, 1e-12));

  st.time_step = 1e-6;
  Simulation fixed(mt, st);
  fixed.add_sphere(0, 0.002, {0, 0, 0});
  fixed.setup();
  CHECK(fixed.dt() == 1e-6);
}

TEST_CASE("A time step far too large stops the run with a diagnosis", "[dem][timestep]") {
  MaterialTable mt;
  mt.add({"grain", 1000, 1e7, 0.3});
  mt.set_pair(0, 0, {0.5, 0.5, 0, true});
  SimulationSettings st;
  st.gravity = {};
  st.time_step_fraction = 0.99;
  st.time_step = 50 * 0.2 * rayleigh_time(0.005, mt[0]);
  Simulation sim(mt, st);
  sim.add_sphere(0, 0.005, {0, 0, 0}, {2, 0, 0});
  sim.add_sphere(0, 0.005, {0.0101, 0, 0}, {-2, 0, 0});
  std::string diagnosis;
  try {
    sim.run_steps(100);
  } catch (const BlowUp& e) {
    diagnosis = e.what();
  }
  INFO(diagnosis);
  CHECK_THAT(diagnosis, Catch::Matchers::Contains("time step") && Catch::Matchers::Contains("particle id"));
}
