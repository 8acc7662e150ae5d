#pragma once
// The particles coarse-graining works on: the component spheres of a snapshot, in the container
// frame, each tagged with its species. Clumps are not treated as points at their centre of mass but
// as their spheres, each carrying its share of the clump's mass (the snapshot's `mass`, shared in
// proportion to r^3), so that a flat chaff flake is spread over the cells it actually spans.
//
// Bodies (grains, flakes) are kept alongside: the report counted particles, not spheres, and the
// slice histogram counts bodies at their centres of mass.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "coarsegrain/container_frame.hpp"
#include "dem/snapshot.hpp"

namespace grainscale::cg {

/// Species = material name. `chaff` marks the species that count as chaff in concentrations, the
/// slice histogram and the surface coverage (the rest is grain). `density`, where given (kg/m^3, the
/// material's solid density), makes a sphere's volume its mass / density, which is its exact share
/// of its clump's volume (overlaps between a clump's spheres counted once); without it the volume is
/// the sphere's own 4/3 pi r^3 (exact for loose spheres, an overestimate for overlapping clumps).
struct SpeciesTable {
  std::vector<std::string> names;
  std::vector<bool> chaff;
  std::map<std::string, double> density;

  int index(const std::string& name) const;  // -1 if absent
  int size() const { return static_cast<int>(names.size()); }
};

/// Species for a snapshot's materials: every material name of `snap`, in file order, with those in
/// `chaff_materials` marked as chaff. Names in `chaff_materials` that the snapshot lacks are allowed
/// (a run without chaff); use the table of the first snapshot for a whole series so indices agree.
SpeciesTable species_from_snapshot(const dem::Snapshot& snap, const std::vector<std::string>& chaff_materials);

/// Spheres and bodies in the container frame (structure of arrays, sphere order of the snapshot).
struct CgParticles {
  double time = 0;
  // spheres
  std::vector<Vec3> position, velocity;
  std::vector<double> radius, mass, volume;
  std::vector<double> number;  // the sphere's share of one body: mass / body mass (1 for a loose sphere)
  std::vector<int> species;
  // bodies
  std::vector<Vec3> body_position;
  std::vector<int> body_species;

  std::size_t size() const { return position.size(); }
};

/// Transform `snap` into the container frame given by `pose`. Species are looked up by material name
/// in `species`; a material not in the table throws InputError. If the snapshot has no /bodies (a
/// hand-built set), every sphere is its own body.
CgParticles container_particles(const dem::Snapshot& snap, const ContainerPose& pose, const SpeciesTable& species);

/// Warnings for species whose bodies have several spheres and no `density`: their spheres get
/// V_p = 4/3 π r³, so the volume fraction (and every concentration by volume) counts the overlaps
/// inside a clump (a 7-sphere wheat clump's spheres hold about twice its volume). `source` names
/// the settings file in the message.
std::vector<std::string> clump_volume_warnings(const dem::Snapshot& snap, const SpeciesTable& species, const std::string& source);

}  // namespace grainscale::cg
