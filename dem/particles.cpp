#include "dem/particles.hpp"

#include <numbers>
#include <stdexcept>

namespace grainscale::dem {

std::size_t Particles::add_sphere(std::uint64_t pid, int mat, double r, double density, const Vec3& pos,
                                  const Vec3& vel, const Vec3& ang_vel) {
  const double m = density * (4.0 / 3.0) * std::numbers::pi * r * r * r;
  const double inert = 0.4 * m * r * r;
  id.push_back(pid);
  material.push_back(mat);
  radius.push_back(r);
  mass.push_back(m);
  inv_mass.push_back(1.0 / m);
  inertia.push_back(inert);
  inv_inertia.push_back(1.0 / inert);
  x.push_back(pos);
  v.push_back(vel);
  omega.push_back(ang_vel);
  force.push_back({});
  torque.push_back({});
  q.push_back({});
  x_at_build.push_back(pos);
  return id.size() - 1;
}

void Particles::permute(const std::vector<std::uint32_t>& p) {
  permute_array(id, scratch_u_, p);
  permute_array(material, scratch_i_, p);
  for (auto* a : {&radius, &mass, &inv_mass, &inertia, &inv_inertia}) permute_array(*a, scratch_d_, p);
  for (auto* a : {&x, &v, &omega, &force, &torque, &x_at_build}) permute_array(*a, scratch_v_, p);
  permute_array(q, scratch_q_, p);
}

std::size_t Particles::slot_of(std::uint64_t pid) const {
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id[i] == pid) return i;
  }
  throw std::out_of_range("no particle with id " + std::to_string(pid));
}

}  // namespace grainscale::dem
