#pragma once
// A bed of ~400 spheres in a box that turns like the tilting platform at its fastest swing: the
// case for a neighbour list measured in the container's frame (dem/list_frame.hpp).
#include <cmath>
#include <memory>

#include "barley_box_fixture.hpp"
#include "dem/container_meshes.hpp"
#include "dem/motion/delayed_motion.hpp"
#include "dem/motion/steady_motion.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/mesh.hpp"

namespace grainscale::dem::testing {

/// The barley and perspex of barley_box_fixture.hpp, damped (restitution 0.2) and with more
/// rolling friction, so that the bed comes to rest in its box within a quarter of a second.
inline MaterialTable grain_and_box() {
  MaterialTable mt = barley_perspex();
  mt.set_pair(0, 0, {0.2, 0.5, 0.1, true});
  mt.set_pair(0, 1, {0.2, 0.5, 0.1, true});
  return mt;
}

/// 384 spheres of 2.6-3.4 mm radius, in a grid, that settle for `settle` s in a 100 x 40 x 60 mm
/// open box, which then turns at `rate` rad/s about the y axis through a pivot 0.3 m below it (the
/// platform's geometry and its fastest swing, 0.26 rad/s: the floor travels ~0.08 m/s in the world).
inline Simulation turning_box(SimulationSettings settings, double settle, double rate) {
  Simulation sim(grain_and_box(), settings);
  int k = 0;
  for (int ix = 0; ix < 12; ++ix)
    for (int iy = 0; iy < 4; ++iy)
      for (int iz = 0; iz < 8; ++iz, ++k) {
        const double r = 0.0026 + 0.0008 * ((k * 7) % 11) / 10.0;
        // (Jittered off the lattice: a simple cubic stack collapses column by column for long after.)
        const double jx = 0.0012 * std::sin(1.7 * k), jy = 0.0014 * std::cos(2.3 * k);
        sim.add_sphere(0, r, {0.006 + 0.0081 * ix + jx, 0.006 + 0.0093 * iy + jy, 0.0036 + 0.0070 * iz});
      }
  sim.add_wall("box", std::make_shared<MeshGeometry>(box_mesh({0, 0, 0}, {0.1, 0.04, 0.06}, {1, 1, 1, 1, 1, 0})), 1);
  auto turn = std::make_shared<SteadyMotion>(Vec3{}, Vec3{0, rate, 0});
  sim.walls().back().set_motion({std::make_shared<DelayedMotion>(turn, settle), {0.05, 0.02, -0.3}});
  return sim;
}

}  // namespace grainscale::dem::testing
