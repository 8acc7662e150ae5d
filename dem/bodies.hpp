#pragma once
// Rigid bodies: what is integrated. Every particle is a body made of one or more component spheres
// (dem/particles.hpp); contacts act on the spheres and are summed on their body. A loose sphere is a
// body with one sphere at its centre.
//
// Like the spheres, bodies are renumbered at every neighbour-list build (Simulation::rebuild), in the
// order of their first sphere's slot: the body and sphere loops of a step then walk both arrays in
// the same spatial order, so a thread's bodies are those whose spheres it owns (no cache lines
// passed between cores) and a large bed reads its bodies' state in order, not at random (the
// per-sphere body reads were the non-linear part of the cost: docs/performance.md). `id` is the
// permanent identity (creation number, 0 .. size()-1 in some order) that output uses; nothing in a
// step depends on the body order, so the renumbering changes no result. `sphere_start` and
// `sphere_slot` list each body's spheres by their current slot, rebuilt after each renumbering.
#include <cstdint>
#include <vector>

#include "dem/permutation.hpp"
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

  /// True while sphere_start / sphere_slot index the bodies of `spheres` spheres (they are made at
  /// each renumbering; bodies or spheres added since have none).
  bool indexed(std::size_t spheres) const { return sphere_start.size() == size() + 1 && sphere_slot.size() == spheres; }
  /// The first body whose first sphere is at or after `slot` (indexed bodies, numbered in the order
  /// of their first sphere): the bodies that start in the slots [s0, s1) are [first_at(s0), first_at(s1)).
  std::size_t first_at(std::size_t slot) const {
    std::size_t lo = 0, hi = size();
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (sphere_slot[sphere_start[mid]] < slot) lo = mid + 1; else hi = mid;
    }
    return lo;
  }

  /// Reorder the per-body arrays (not sphere_start / sphere_slot, which the caller rebuilds) so that
  /// new index k holds what old index new_to_old[k] held. Allocation-free once the scratch buffers
  /// have reached the body count.
  void permute(const std::vector<std::uint32_t>& new_to_old);
  /// The same, with the indices it moves listed (dem/permutation.hpp): allocation-free.
  void permute(const Renumbering& r);

  /// Current index of the body with this id (linear search; for tests and diagnostics).
  std::size_t index_of(std::uint64_t body_id) const;
  /// The current indices in id order: element k is the index of the body with id k (for output).
  std::vector<std::size_t> indices_by_id() const;

 private:
  PermuteScratch scratch_;
};

}  // namespace grainscale::dem
