#include "coarsegrain/cg_particles.hpp"

#include <algorithm>
#include <numbers>
#include <unordered_map>

#include "dem/input_error.hpp"

namespace grainscale::cg {

int SpeciesTable::index(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

SpeciesTable species_from_snapshot(const dem::Snapshot& snap, const std::vector<std::string>& chaff_materials) {
  SpeciesTable t;
  for (const std::string& m : snap.material_names) {
    t.names.push_back(m);
    t.chaff.push_back(std::find(chaff_materials.begin(), chaff_materials.end(), m) != chaff_materials.end());
  }
  return t;
}

CgParticles container_particles(const dem::Snapshot& snap, const ContainerPose& pose, const SpeciesTable& species) {
  // Snapshot material index -> species index, by name.
  std::vector<int> species_of_material(snap.material_names.size());
  for (std::size_t m = 0; m < snap.material_names.size(); ++m) {
    species_of_material[m] = species.index(snap.material_names[m]);
  }
  const std::size_t n = snap.id.size();
  CgParticles p;
  p.time = snap.time;
  p.position.resize(n);
  p.velocity.resize(n);
  p.radius = snap.radius;
  p.mass = snap.mass;
  p.volume.resize(n);
  p.number.assign(n, 1.0);
  p.species.resize(n);

  std::unordered_map<std::uint64_t, std::size_t> body_row;
  for (std::size_t b = 0; b < snap.body_id.size(); ++b) body_row.emplace(snap.body_id[b], b);

  for (std::size_t k = 0; k < n; ++k) {
    const int s = species_of_material[static_cast<std::size_t>(snap.material[k])];
    if (s < 0) {
      throw InputError("coarse-graining: material '" + snap.material_names[static_cast<std::size_t>(snap.material[k])] +
                       "' of the snapshot at t = " + std::to_string(snap.time) +
                       " s is not among the species of the series (taken from its first snapshot)");
    }
    p.species[k] = s;
    p.position[k] = to_container_position(pose, snap.position[k]);
    p.velocity[k] = to_container_velocity(pose, snap.position[k], snap.velocity[k]);
    const auto rho = species.density.find(species.names[static_cast<std::size_t>(s)]);
    const double r = snap.radius[k];
    p.volume[k] = rho != species.density.end() ? snap.mass[k] / rho->second : 4.0 / 3.0 * std::numbers::pi * r * r * r;
    if (!snap.body.empty()) {
      const auto it = body_row.find(snap.body[k]);
      if (it != body_row.end() && snap.body_mass[it->second] > 0) p.number[k] = snap.mass[k] / snap.body_mass[it->second];
    }
  }

  if (snap.body_id.empty() || snap.body.empty()) {
    p.body_position = p.position;
    p.body_species = p.species;
  } else {
    // A body's species is that of its spheres (a body is made of one material).
    std::vector<int> bs(snap.body_id.size(), -1);
    for (std::size_t k = 0; k < n; ++k) {
      const auto it = body_row.find(snap.body[k]);
      if (it != body_row.end()) bs[it->second] = p.species[k];
    }
    for (std::size_t b = 0; b < snap.body_id.size(); ++b) {
      if (bs[b] < 0) continue;  // a body without spheres in the file: nothing to count
      p.body_position.push_back(to_container_position(pose, snap.body_position[b]));
      p.body_species.push_back(bs[b]);
    }
  }
  return p;
}

std::vector<std::string> clump_volume_warnings(const dem::Snapshot& snap, const SpeciesTable& species, const std::string& source) {
  std::unordered_map<std::uint64_t, int> spheres_of_body;
  for (const std::uint64_t b : snap.body) ++spheres_of_body[b];
  std::vector<bool> clumped(static_cast<std::size_t>(species.size()), false);
  for (std::size_t k = 0; k < snap.body.size() && k < snap.material.size(); ++k) {
    if (spheres_of_body[snap.body[k]] < 2) continue;
    const int sp = species.index(snap.material_names[static_cast<std::size_t>(snap.material[k])]);
    if (sp >= 0) clumped[static_cast<std::size_t>(sp)] = true;
  }
  std::vector<std::string> out;
  for (std::size_t k = 0; k < clumped.size(); ++k) {
    if (clumped[k] && !species.density.count(species.names[k])) {
      out.push_back(source + ": species '" + species.names[k] + "' is made of clumps and has no 'density': its volume "
                    "fraction counts the overlaps of each clump's spheres (too high), and so do concentrations by volume; "
                    "give species." + species.names[k] + ".density (kg/m^3) for the exact clump volume");
    }
  }
  return out;
}

}  // namespace grainscale::cg
