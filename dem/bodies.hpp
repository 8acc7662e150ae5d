#pragma once
// Rigid bodies: what is integrated. Every particle is a body made of one or more component spheres
// (dem/particles.hpp); contacts act on the spheres and are summed on their body. A loose sphere is a
// body with one sphere at its centre.
//
// Bodies keep their creation order (spheres are the ones renumbered for locality); `sphere_start` and
// `sphere_slot` list each body's spheres by their current slot, rebuilt after each renumbering.
#include <cstdint>
#include <vector>

#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

struct Bodies {
  std::vector<std::uint64_t> id;
  std::vector<std::int32_t> shape;      // index into the simulation's shape names; -1 for a loose sphere
  std::vector<double> mass, inv_mass;
  std::vector<Vec3> inertia;            // principal moments of inertia, kg m^2
  std::vector<Vec3> x, v;               // centre of mass, its velocity
  std::vector<Vec3> L, omega;           // angular momentum and angular velocity, world frame
  std::vector<Quat> q;                  // principal frame -> world
  std::vector<Vec3> force, torque;      // summed from the spheres, plus gravity
  std::vector<std::uint32_t> sphere_start, sphere_slot;  // CSR: spheres of body b are
                                                         // sphere_slot[sphere_start[b] .. sphere_start[b+1])

  std::size_t size() const { return id.size(); }
};

}  // namespace grainscale::dem
