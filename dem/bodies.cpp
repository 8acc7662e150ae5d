#include "dem/bodies.hpp"

#include <stdexcept>
#include <string>

namespace grainscale::dem {

void Bodies::permute(const std::vector<std::uint32_t>& new_to_old) { permute(Renumbering(new_to_old)); }

void Bodies::permute(const Renumbering& p) {
  scratch_.apply(id, p);
  scratch_.apply(shape, p);
  for (auto* a : {&mass, &inv_mass}) scratch_.apply(*a, p);
  for (auto* a : {&inertia, &x, &v, &L, &omega, &force, &torque}) scratch_.apply(*a, p);
  scratch_.apply(q, p);
}

std::size_t Bodies::index_of(std::uint64_t body_id) const {
  for (std::size_t k = 0; k < id.size(); ++k) {
    if (id[k] == body_id) return k;
  }
  throw std::out_of_range("no body with id " + std::to_string(body_id));
}

std::vector<std::size_t> Bodies::indices_by_id() const {
  std::vector<std::size_t> at(id.size());  // (ids are 0 .. size()-1: Simulation::restore checks)
  for (std::size_t k = 0; k < id.size(); ++k) at[id[k]] = k;
  return at;
}

}  // namespace grainscale::dem
