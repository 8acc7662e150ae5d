#include "dem/particles.hpp"

#include <numbers>
#include <stdexcept>

namespace grainscale::dem {

std::size_t Particles::add_sphere(std::uint64_t pid, int mat, double r, double density, const Vec3& pos,
                                  const Vec3& vel, const Vec3& ang_vel) {
  const double m = density * (4.0 / 3.0) * std::numbers::pi * r * r * r;
  const std::size_t s = add_component(pid, static_cast<std::uint32_t>(size()), mat, r, {}, m, 0.4 * m * r * r, m, pos);
  v[s] = vel;
  omega[s] = ang_vel;
  return s;
}

std::size_t Particles::add_component(std::uint64_t pid, std::uint32_t b, int mat, double r, const Vec3& off,
                                     double body_mass, double body_min_inertia, double share, const Vec3& pos) {
  id.push_back(pid);
  material.push_back(mat);
  body.push_back(b);
  offset.push_back(off);
  radius.push_back(r);
  mass.push_back(body_mass);
  inertia.push_back(body_min_inertia);
  mass_share.push_back(share);
  x.push_back(pos);
  v.push_back({});
  omega.push_back({});
  force.push_back({});
  torque.push_back({});
  q.push_back({});
  x_at_build.push_back(pos);
  return id.size() - 1;
}

void Particles::permute(const std::vector<std::uint32_t>& new_to_old) { permute(Renumbering(new_to_old)); }

void Particles::permute(const Renumbering& p) {
  scratch_.apply(id, p);
  scratch_.apply(material, p);
  scratch_.apply(body, p);
  for (auto* a : {&radius, &mass, &inertia, &mass_share}) scratch_.apply(*a, p);
  for (auto* a : {&offset, &x, &v, &omega, &force, &torque, &x_at_build}) scratch_.apply(*a, p);
  scratch_.apply(q, p);
}

std::size_t Particles::slot_of(std::uint64_t pid) const {
  for (std::size_t i = 0; i < id.size(); ++i) {
    if (id[i] == pid) return i;
  }
  throw std::out_of_range("no particle with id " + std::to_string(pid));
}

}  // namespace grainscale::dem
