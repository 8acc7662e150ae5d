#include "continuum/closure/container_gravity.hpp"

#include <algorithm>
#include <cmath>

#include "dem/input_error.hpp"
#include "dem/quaternion.hpp"

namespace grainscale::continuum::closure {

using dem::Vec3;

ContainerGravity::ContainerGravity(std::shared_ptr<const dem::MotionProfile> motion, ContainerPlacement placement)
    : motion_(std::move(motion)), p_(placement) {
  if (std::abs(dem::norm(p_.x_axis) - 1) > 1e-9 || std::abs(dem::norm(p_.z_axis) - 1) > 1e-9 ||
      std::abs(dem::dot(p_.x_axis, p_.z_axis)) > 1e-9) {
    throw InputError("container placement: x_axis and z_axis must be orthogonal unit vectors");
  }
  if (!(p_.gravity > 0)) throw InputError("container placement: gravity must be positive");
}

dem::RigidMotionState ContainerGravity::state(double t) const {
  return motion_ ? motion_->at(t) : dem::RigidMotionState{};
}

void ContainerGravity::components(const dem::RigidMotionState& s, double x, double& g_t, double& g_n) const {
  const Vec3 x0 = p_.origin + x * p_.x_axis + p_.reference_height * p_.z_axis;
  const Vec3 r = dem::rotate(s.rotation, x0 - p_.pivot);
  const Vec3 accel = s.acceleration + dem::cross(s.angular_acceleration, r) +
                     dem::cross(s.angular_velocity, dem::cross(s.angular_velocity, r));
  const Vec3 g_world{0, 0, -p_.gravity};
  const Vec3 g_body = dem::rotate(dem::conjugate(s.rotation), g_world - accel);  // (G1)
  g_t = dem::dot(g_body, p_.x_axis);
  g_n = -dem::dot(g_body, p_.z_axis);
}

double ContainerGravity::tilt(const dem::RigidMotionState& s) const {
  const Vec3 ex = dem::rotate(s.rotation, p_.x_axis);  // the floor direction now, world frame
  return std::asin(std::clamp(-dem::dot(ex, p_.z_axis), -1.0, 1.0));
}

}  // namespace grainscale::continuum::closure
