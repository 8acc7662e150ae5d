#pragma once
// Any motion, begun at a later time: at rest (identity, phase 0) until `start`, then the inner
// profile run from its own t = 0. Lets a container be filled and settled before it starts moving
// (scenario key `motion.start_time`).
#include <memory>
#include <sstream>

#include "dem/motion_profile.hpp"

namespace grainscale::dem {

class DelayedMotion final : public MotionProfile {
 public:
  DelayedMotion(std::shared_ptr<const MotionProfile> inner, double start) : inner_(std::move(inner)), start_(start) {}
  RigidMotionState at(double t) const override { return t < start_ ? RigidMotionState{} : inner_->at(t - start_); }
  double period() const override { return inner_->period(); }
  std::string describe() const override {
    std::ostringstream o;
    o << inner_->describe() << ", from t = " << start_ << " s";
    return o.str();
  }

 private:
  std::shared_ptr<const MotionProfile> inner_;
  double start_;
};

}  // namespace grainscale::dem
