#include "dem/motion/motion_from_yaml.hpp"

#include <numbers>

#include "dem/input_error.hpp"
#include "dem/motion/delayed_motion.hpp"
#include "dem/motion/platform_tilt.hpp"
#include "dem/motion/sinusoidal_motion.hpp"
#include "dem/motion/steady_motion.hpp"
#include "dem/motion/tabulated_motion.hpp"

namespace grainscale::dem {

namespace {
constexpr double kDeg = std::numbers::pi / 180;
}

std::shared_ptr<const MotionProfile> motion_from_yaml(YamlMap m, double end_time) {
  const std::string type = m.choice("type", {"platform", "sinusoids", "record", "steady"});
  const double start = m.number_or("start_time", 0.0, Range::non_negative());
  std::shared_ptr<const MotionProfile> out;
  if (type == "platform") {
    PlatformTilt::Params p;
    p.amplitude = m.number("amplitude_deg", {0, 90, true, false}) * kDeg;
    p.frequency = m.number_or("frequency", 0.1, {0, 100, true, false});
    p.pause = m.number_or("pause", 4.0, Range::non_negative());
    p.axis = m.vec3_or("axis", {0, 1, 0});
    if (norm(p.axis) == 0) throw InputError(m.where("axis") + " must not be the zero vector");
    p.start_level = m.choice_or("start", "level", {"level", "end"}) == "level";
    out = std::make_shared<PlatformTilt>(p);
  } else if (type == "sinusoids") {
    static const char* names[6] = {"roll", "pitch", "yaw", "surge", "sway", "heave"};
    std::array<SinusoidalMotion::Dof, 6> d{};
    bool any = false;
    for (int k = 0; k < 6; ++k) {
      auto s = m.optional_map(names[k]);
      if (!s) continue;
      any = true;
      d[k].amplitude = k < 3 ? s->number("amplitude_deg", {0, 180, false, false}) * kDeg
                             : s->number("amplitude", {0, 1e3, false, false});
      d[k].frequency = 1 / s->number("period", {0, 1e7, true, false});
      d[k].phase = s->number_or("phase_deg", 0, {-360, 360, false, false}) * kDeg;
      s->finish();
    }
    if (!any) throw InputError(m.where("type") + ": 'sinusoids' needs at least one of roll, pitch, yaw, surge, sway, heave");
    out = std::make_shared<SinusoidalMotion>(d);
  } else if (type == "steady") {
    const Vec3 v = m.vec3_or("velocity", {}), w = m.vec3_or("angular_velocity", {});
    if (norm(v) == 0 && norm(w) == 0) throw InputError(m.where("type") + ": 'steady' needs a velocity or an angular_velocity");
    out = std::make_shared<SteadyMotion>(v, w);
  } else {
    auto rec = std::make_shared<TabulatedMotion>(TabulatedMotion::load(resolve_beside(m.file(), m.string("file"))));
    if (rec->end_time() < end_time - start || rec->start_time() > 0) {
      throw InputError(m.where("file") + ": the record covers t = " + std::to_string(rec->start_time()) + " to " +
                       std::to_string(rec->end_time()) + " s but the run needs 0 to " +
                       std::to_string(end_time - start) + " s of it");
    }
    out = rec;
  }
  m.finish();
  if (start > 0) out = std::make_shared<DelayedMotion>(out, start);
  return out;
}

}  // namespace grainscale::dem
