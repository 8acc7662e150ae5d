#pragma once
// Shared set-ups for the flow-closure tests: a container held at a fixed tilt, and section settings.
#include <cmath>
#include <memory>
#include <string>

#include "continuum/closure/shallow_granular_flow.hpp"
#include "dem/motion_profile.hpp"
#include "dem/quaternion.hpp"

namespace closure_test {

using namespace grainscale;

/// Held at tilt θ about +y (the +x end down), at rest.
class FixedTilt final : public dem::MotionProfile {
 public:
  explicit FixedTilt(double theta) : theta_(theta) {}
  dem::RigidMotionState at(double) const override {
    dem::RigidMotionState s;
    s.rotation = dem::axis_angle({0, 1, 0}, theta_);
    return s;
  }
  double period() const override { return 0; }
  std::string describe() const override { return "fixed tilt"; }

 private:
  double theta_;
};

inline continuum::closure::ContainerGravity tilted(double theta_rad, double g = 9.81) {
  continuum::closure::ContainerPlacement p;
  p.gravity = g;
  return continuum::closure::ContainerGravity(std::make_shared<FixedTilt>(theta_rad), p);
}

inline constexpr double kDeg = M_PI / 180;

/// A section of `length` m in `nx` cells with internal friction φ, basal friction δ (degrees) and
/// flowing-layer depth ℓ (m).
inline continuum::closure::SectionSettings section(double length, int nx, double phi_deg, double delta_deg,
                                                    double ell) {
  continuum::closure::SectionSettings s;
  s.length = length;
  s.nx = nx;
  s.friction.internal_deg = phi_deg;
  s.friction.basal_deg = delta_deg;
  s.friction.layer_depth = ell;
  return s;
}

}  // namespace closure_test
