#pragma once
// Gravity as the grain feels it in a moving container's own frame (Gray, Wieland & Hutter, Proc. R.
// Soc. A 455, 1999, for avalanches in moving/rotating frames): for a point fixed in the container,
//
//   g_eff = R(t)ᵀ [ g_world − d″ − α × r − ω × (ω × r) ],   r = R(t)(x₀ − pivot)            (G1)
//
// (x₀ the point's rest position; R, ω, α, d″ from the same MotionProfile the DEM uses, so a
// container off the rotation axis, like the report's box at the platform's edge or a hold above a
// ship's roll axis, feels the lever-arm accelerations). The closure needs two components at each
// position x along the floor: along the floor, g_t = g_eff · e_x (positive: grain driven to +x), and
// into the floor, g_n = −g_eff · e_z. The Coriolis acceleration of the moving grain, −2 ω × u, is
// left out: for u along x and ω across the section it only changes g_n by 2 ω u, below 1 % for the
// speeds and roll rates of interest (docs/hold_prediction.md).
#include <memory>

#include "dem/motion_profile.hpp"
#include "dem/vec3.hpp"

namespace grainscale::continuum::closure {

struct ContainerPlacement {
  dem::Vec3 origin{0, 0, 0};   // world position at rest of the floor point x = 0 of the section
  dem::Vec3 x_axis{1, 0, 0};   // section direction at rest (unit), horizontal
  dem::Vec3 z_axis{0, 0, 1};   // up at rest (unit)
  dem::Vec3 pivot{0, 0, 0};    // the motion's pivot, world frame
  double reference_height = 0; // height above the floor at which (G1) is evaluated (e.g. mid-bed) [m]
  double gravity = 9.81;       // [m/s²]
};

class ContainerGravity {
 public:
  /// `motion` may be null: a container at rest.
  ContainerGravity(std::shared_ptr<const dem::MotionProfile> motion, ContainerPlacement placement);

  /// The motion state at t; pass it to components() for every x (one profile evaluation per step).
  dem::RigidMotionState state(double t) const;
  /// (g_t, g_n) at position x along the floor.
  void components(const dem::RigidMotionState& s, double x, double& g_t, double& g_n) const;
  /// Tilt of the floor about the section's normal, rad (positive: +x end down).
  double tilt(const dem::RigidMotionState& s) const;
  const ContainerPlacement& placement() const { return p_; }
  const dem::MotionProfile* motion() const { return motion_.get(); }

 private:
  std::shared_ptr<const dem::MotionProfile> motion_;
  ContainerPlacement p_;
};

}  // namespace grainscale::continuum::closure
