#pragma once
// The report's barley and perspex (Table 1) as an in-code material table, and a box of barley-like
// spheres on a jittered lattice: the small settling bed several tests share.
#include <memory>

#include "dem/random.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/box.hpp"

namespace grainscale::dem::testing {

inline MaterialTable barley_perspex() {
  MaterialTable mt;
  mt.add({"grain", 1380, 2.6e6, 0.3});
  mt.add({"perspex", 1190, 7.97e8, 0.38});
  mt.set_pair(0, 0, {0.5, 0.35, 0.08, true});
  mt.set_pair(0, 1, {0.5, 0.25, 0.01, true});
  return mt;
}

/// nx x ny x nz spheres of radius ~3 mm (+-10 %) on a 7 mm lattice with small random offsets and
/// sideways velocities, in an open-topped box just wide enough: they fall, collide and settle.
/// (`st`: other settings; its rolling model is replaced by `model`.)
inline Simulation barley_box(RollingModel model, int nx, int ny, int nz, std::uint64_t seed,
                             SimulationSettings st = {}) {
  st.rolling.model = model;
  Simulation sim(barley_perspex(), st);
  Random rng(seed);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        const Vec3 x{0.005 + 0.007 * i + 2e-4 * rng.uniform(), 0.005 + 0.007 * j + 2e-4 * rng.uniform(),
                     0.005 + 0.007 * k};
        sim.add_sphere(0, 0.003 * (1 + 0.1 * (2 * rng.uniform() - 1)), x,
                       {0.2 * (rng.uniform() - 0.5), 0.2 * (rng.uniform() - 0.5), 0});
      }
  const Vec3 hi{0.003 + 0.007 * nx, 0.003 + 0.007 * ny, 0.2};
  sim.add_wall("box", std::make_shared<BoxGeometry>(Vec3{0, 0, 0}, hi, std::array<bool, 6>{1, 1, 1, 1, 1, 0}), 1);
  return sim;
}

}  // namespace grainscale::dem::testing
