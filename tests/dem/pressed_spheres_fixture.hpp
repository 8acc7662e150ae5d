#pragma once
// A big sphere (radius 10 mm, moving and spinning) with `count` small ones (1 mm) pressed onto it
// from random directions by up to 40 um, each with a random velocity and spin: one sphere owns more
// contacts than a pair batch or a small ring of partner shares holds. `rng` is drawn from in order,
// so a test may go on drawing from it.
#include <random>

#include "dem/particles.hpp"

namespace grainscale::dem::testing {

inline Particles big_sphere_pressed(int material, int count, std::mt19937_64& rng) {
  Particles p;
  std::uniform_real_distribution<double> u(-1, 1);
  const double big = 0.01, small = 0.001;
  p.add_sphere(0, material, big, 1380, {0, 0, 0}, {0.01, 0, 0}, {0, 0, 5});
  for (int s = 1; s <= count; ++s) {
    Vec3 dir{u(rng), u(rng), u(rng)};
    dir = (1.0 / norm(dir)) * dir;
    const double gap = -2e-5 * (1 + u(rng));  // pressed in by up to 40 um
    p.add_sphere(s, material, small, 1380, (big + small + gap) * dir, 0.05 * Vec3{u(rng), u(rng), u(rng)},
                 20 * Vec3{u(rng), u(rng), u(rng)});
  }
  return p;
}

}  // namespace grainscale::dem::testing
