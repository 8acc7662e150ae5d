#include "dem/bodies.hpp"

#include <stdexcept>
#include <string>

#include "dem/particles.hpp"

namespace grainscale::dem {

void Bodies::permute(const std::vector<std::uint32_t>& p) {
  permute_array(id, scratch_u_, p);
  permute_array(shape, scratch_i_, p);
  for (auto* a : {&mass, &inv_mass}) permute_array(*a, scratch_d_, p);
  for (auto* a : {&inertia, &x, &v, &L, &omega, &force, &torque}) permute_array(*a, scratch_v_, p);
  permute_array(q, scratch_q_, p);
}

std::size_t Bodies::index_of(std::uint64_t body_id) const {
  for (std::size_t k = 0; k < id.size(); ++k) {
    if (id[k] == body_id) return k;
  }
  throw std::out_of_range("no body with id " + std::to_string(body_id));
}

}  // namespace grainscale::dem
