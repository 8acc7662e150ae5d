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
/// open box, which then turns at `rate` rad/s about the y axis through a pivot 0.3 m below its floor
/// (the platform's geometry and its fastest swing, 0.26 rad/s: the floor travels ~0.08 m/s in the
/// world).
/// With `bar`: the box is lifted instead, turning at `rate` about a pivot 0.5 m to its side (rate
/// < 0: it rises at |rate| x 0.5 m/s), under a 10 x 16 mm bar fixed in the world 96 mm above its
/// floor at the start, which the settled bed's surface (~30 mm) meets once the box has risen 66 mm:
/// a wall that moves in the box's frame, for the near-wall masks. The box sits 0.5 m aside of the
/// world's origin (its rest pose), so that its frame's coordinates are not the world's.
inline Simulation turning_box(SimulationSettings settings, double settle, double rate, bool bar = false) {
  Simulation sim(grain_and_box(), settings);
  const Vec3 at = bar ? Vec3{-0.5, 0, 0} : Vec3{};
  const Vec3 pivot = bar ? Vec3{-0.95, 0.02, 0.02} : Vec3{0.05, 0.02, -0.3};
  const Vec3 bar_lo{0.045, 0.012, 0.096}, bar_hi{0.055, 0.028, 0.16};
  int k = 0;
  for (int ix = 0; ix < 12; ++ix)
    for (int iy = 0; iy < 4; ++iy)
      for (int iz = 0; iz < 8; ++iz, ++k) {
        const double r = 0.0026 + 0.0008 * ((k * 7) % 11) / 10.0;
        // (Jittered off the lattice: a simple cubic stack collapses column by column for long after.)
        const double jx = 0.0012 * std::sin(1.7 * k), jy = 0.0014 * std::cos(2.3 * k);
        const Vec3 x{0.006 + 0.0081 * ix + jx, 0.006 + 0.0093 * iy + jy, 0.0036 + 0.0070 * iz};
        const bool under_bar = x.x > bar_lo.x - r && x.x < bar_hi.x + r && x.y > bar_lo.y - r && x.y < bar_hi.y + r;
        if (bar && under_bar && x.z > bar_lo.z - r) continue;
        sim.add_sphere(0, r, at + x);
      }
  WallPose rest;
  rest.origin = at;
  sim.add_wall("box", std::make_shared<MeshGeometry>(box_mesh({0, 0, 0}, {0.1, 0.04, 0.06}, {1, 1, 1, 1, 1, 0})), 1, rest);
  auto turn = std::make_shared<SteadyMotion>(Vec3{}, Vec3{0, rate, 0});
  sim.walls().back().set_motion({std::make_shared<DelayedMotion>(turn, settle), pivot});
  if (bar) sim.add_wall("bar", std::make_shared<MeshGeometry>(box_mesh(at + bar_lo, at + bar_hi, {1, 1, 1, 1, 1, 1})), 1);
  return sim;
}

}  // namespace grainscale::dem::testing
