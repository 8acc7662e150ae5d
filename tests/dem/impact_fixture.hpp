#pragma once
// Two-body impact set-ups shared by the contact-model tests: a sphere hitting a rigid plane, or two
// spheres hitting each other, in zero gravity, run until they separate.
#include <cmath>
#include <limits>
#include <memory>

#include "dem/simulation.hpp"
#include "dem/walls/plane.hpp"

namespace grainscale::dem::testing {

struct Solid {
  double youngs = 0, poisson = 0, density = 0;
};

inline Material make_material(const std::string& name, const Solid& s) {
  return {name, s.density, s.youngs / (2 * (1 + s.poisson)), s.poisson};
}

/// Materials "ball", "ball2" and a rigid "wall", all pairs with the given properties.
inline MaterialTable impact_materials(const Solid& ball, const Solid& ball2, double e, double mu, double mu_r = 0) {
  MaterialTable t;
  t.add(make_material("ball", ball));
  t.add(make_material("ball2", ball2));
  t.add({"wall", 1000, std::numeric_limits<double>::infinity(), ball.poisson});
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) t.set_pair(a, b, {e, mu, mu_r, true});
  return t;
}

inline SimulationSettings impact_settings(double fraction = 0.01) {
  SimulationSettings s;
  s.gravity = {0, 0, 0};
  s.time_step_fraction = fraction;
  s.rolling.model = RollingModel::none;
  return s;
}

/// Outcome of one impact: velocities after separation and what happened during contact.
struct ImpactResult {
  Vec3 v1, w1, v2, w2;   // after separation (v2, w2 unused for wall impacts)
  double duration = 0;   // s with the bodies in contact
  double max_overlap = 0;
  double max_force = 0;  // |force on body 1|
};

/// Run `sim` (two spheres, or one sphere and walls) until contact has begun and ended again.
inline ImpactResult run_impact(Simulation& sim) {
  ImpactResult r;
  sim.setup();
  bool touched = false;
  for (int step = 0; step < 10'000'000; ++step) {
    sim.step();
    const ForceDiagnostics& d = sim.diagnostics();
    const bool touching = d.contacts + d.wall_contacts > 0;
    const Particles& p = sim.particles();
    if (touching) {
      touched = true;
      r.duration += sim.dt();
      r.max_force = std::max(r.max_force, norm(p.force[p.slot_of(0)]));
      r.max_overlap = std::max(r.max_overlap, d.max_overlap_ratio * p.radius[p.slot_of(0)]);
    } else if (touched) {
      break;
    }
  }
  const Particles& p = sim.particles();
  r.v1 = p.v[p.slot_of(0)];
  r.w1 = p.omega[p.slot_of(0)];
  if (p.size() > 1) {
    r.v2 = p.v[p.slot_of(1)];
    r.w2 = p.omega[p.slot_of(1)];
  }
  return r;
}

/// A sphere of radius r just touching the plane z = 0 from above, moving with v and spin w.
inline ImpactResult sphere_on_wall(const MaterialTable& mt, double r, const Vec3& v, const Vec3& w,
                                   double fraction = 0.01) {
  Simulation sim(mt, impact_settings(fraction));
  sim.add_sphere(mt.index("ball"), r, {0, 0, r}, v, w);
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), mt.index("wall"));
  return run_impact(sim);
}

}  // namespace grainscale::dem::testing
