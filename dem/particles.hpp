#pragma once
// Sphere state as a structure of arrays: each field is one contiguous array indexed by the sphere's
// current slot. Slots are renumbered (permute) when the neighbour list reorders spheres for cache
// locality; `id` is the permanent identity that output and contact histories use.
//
// Every sphere belongs to a rigid body (dem/bodies.hpp): a loose sphere is its own body, a clump's
// spheres share one. Positions and velocities here are derived from the body each step; `mass` and
// `inertia` are the body's (what a contact model needs for its effective mass and rolling inertia),
// `mass_share` is the part of the body's mass this sphere stands for (output, coarse-graining).
#include <cstdint>
#include <vector>

#include "dem/permutation.hpp"
#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

struct Particles {
  std::vector<std::uint64_t> id;
  std::vector<std::int32_t> material;
  std::vector<std::uint32_t> body;           // index of the owning body
  std::vector<Vec3> offset;                  // centre relative to the body's centre of mass, body frame
  std::vector<double> radius;
  std::vector<double> mass;                  // the body's mass
  std::vector<double> inertia;               // the body's smallest principal moment of inertia
  std::vector<double> mass_share;            // this sphere's share of the body's mass
  std::vector<Vec3> x, v, omega;             // position, velocity, angular velocity (world frame)
  std::vector<Vec3> force, torque;           // accumulated by the force field each step
  std::vector<Quat> q;                       // orientation (body -> world)
  std::vector<Vec3> x_at_build;              // positions when the neighbour list was built

  std::size_t size() const { return id.size(); }

  /// Append a loose solid sphere (its own body, numbered by its slot); returns its slot.
  std::size_t add_sphere(std::uint64_t pid, int mat, double r, double density, const Vec3& pos, const Vec3& vel = {},
                         const Vec3& ang_vel = {});
  /// Append a component sphere of body `b`; returns its slot.
  std::size_t add_component(std::uint64_t pid, std::uint32_t b, int mat, double r, const Vec3& offset_in_body,
                            double body_mass, double body_min_inertia, double share, const Vec3& pos);

  /// Reorder every array so that new slot i holds what old slot new_to_old[i] held.
  /// Allocation-free once the scratch buffers have reached the particle count.
  void permute(const std::vector<std::uint32_t>& new_to_old);
  /// The same, with the slots it moves listed (dem/permutation.hpp): allocation-free.
  void permute(const Renumbering& r);

  /// Slot of the particle with this id (linear search; for tests and diagnostics).
  std::size_t slot_of(std::uint64_t pid) const;

 private:
  PermuteScratch scratch_;
};

}  // namespace grainscale::dem
