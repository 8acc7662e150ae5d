#include "dem/scenario.hpp"

#include <array>
#include <charconv>
#include <cstdio>
#include <limits>
#include <sstream>

#include "dem/input_error.hpp"
#include "dem/time_step.hpp"
#include "dem/container_meshes.hpp"
#include "dem/motion/motion_from_yaml.hpp"
#include "dem/walls/box.hpp"
#include "dem/walls/mesh.hpp"
#include "dem/walls/cylinder.hpp"
#include "dem/walls/plane.hpp"
#include "dem/wall_clearance.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::dem {

namespace {

std::array<bool, 6> closed_faces(YamlMap& w) {
  std::array<bool, 6> closed{true, true, true, true, true, true};
  const std::vector<std::string> faces{"-x", "+x", "-y", "+y", "-z", "+z"};
  for (const std::string& face : w.choices_or_empty("open", faces)) {
    for (int f = 0; f < 6; ++f) {
      if (faces[f] == face) closed[f] = false;
    }
  }
  return closed;
}

WallSpec parse_wall(YamlMap w, double end_time) {
  WallSpec spec;
  spec.name = w.string("name");
  spec.material = w.string("material");
  const std::string type =
      w.choice("type", {"plane", "box", "cylinder", "stl", "box_mesh", "pipe", "tray", "cylinder_mesh"});
  spec.pose.origin = w.vec3_or("origin", {});
  if (auto m = w.optional_map("motion")) {
    spec.motion.profile = motion_from_yaml(*m, end_time);
    spec.motion.pivot = w.vec3_or("pivot", {});
  } else if (w.has("pivot")) {
    throw InputError(w.where("pivot") + " is only meaningful with 'motion'");
  }
  const std::string label = w.file() + ": wall '" + spec.name + "'";
  auto mesh_wall = [&](TriangleMesh mesh) {
    spec.geometry = std::make_shared<MeshGeometry>(std::move(mesh), w.number_or("cell_size", 0.0, Range::non_negative()),
                                                   label);
  };
  auto segments = [&] { return static_cast<int>(w.integer_or("segments", 64, 8, 4096)); };
  if (type == "stl") {
    mesh_wall(load_stl(resolve_beside(w.file(), w.string("file")), w.number_or("scale", 1.0, Range::positive())));
  } else if (type == "box_mesh") {
    const Vec3 lo = w.vec3("min"), hi = w.vec3("max");
    if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw InputError(w.where("max") + " must exceed 'min' in x, y and z");
    mesh_wall(box_mesh(lo, hi, closed_faces(w), static_cast<int>(w.integer_or("compartments", 1, 1, 1000))));
  } else if (type == "pipe") {
    const double r = w.number("radius", Range::positive()), len = w.number("length", Range::positive());
    mesh_wall(pipe_mesh(r, len, segments()));
  } else if (type == "tray") {
    const double r = w.number("radius", Range::positive());
    mesh_wall(tray_mesh(r, w.number_or("rim_height", 0.0, Range::non_negative()), segments()));
  } else if (type == "cylinder_mesh") {
    const double r = w.number("radius", Range::positive()), h = w.number("height", Range::positive());
    const bool bottom = w.boolean_or("bottom", true), top = w.boolean_or("top", false);
    mesh_wall(cylinder_mesh(r, h, segments(), bottom, top));
  } else if (type == "plane") {
    const Vec3 normal = w.vec3("normal");
    if (norm(normal) == 0) throw InputError(w.where("normal") + " must not be the zero vector");
    spec.geometry = std::make_shared<PlaneGeometry>(w.vec3_or("point", {}), normal);
  } else if (type == "box") {
    const Vec3 lo = w.vec3("min"), hi = w.vec3("max");
    if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw InputError(w.where("max") + " must exceed 'min' in x, y and z");
    spec.geometry = std::make_shared<BoxGeometry>(lo, hi, closed_faces(w));
  } else {
    const double radius = w.number("radius", Range::positive());
    const double height = w.number("height", Range::positive());
    const bool inside = w.boolean_or("inside", true);
    spec.geometry = std::make_shared<CylinderGeometry>(radius, 0.0, height, inside, w.boolean_or("bottom", inside),
                                                       w.boolean_or("top", false));
  }
  w.finish();
  return spec;
}

BatchSpec parse_batch(YamlMap p, double scale) {
  BatchSpec b;
  b.material = p.string("material");
  b.batch.label = p.file() + ": " + p.path();
  if (p.has("shape")) {
    // Clumps: the shape file's spheres, scaled by the scenario's particle scale factor.
    Shape shape = load_shape(resolve_beside(p.file(), p.string("shape")));
    for (auto& c : shape.spheres) c.center = scale * c.center, c.radius *= scale;
    b.batch.shape = std::make_shared<const Shape>(std::move(shape));
    b.particle_mass = p.number_or("particle_mass", 0.0, Range::positive());
    if (p.has("diameter")) throw InputError(p.where("diameter") + ": give either 'shape' or 'diameter', not both");
  } else {
    b.batch.diameter = p.number("diameter", {0, 10, true, false});
    b.batch.diameter_spread = p.number_or("diameter_spread", 0, {0, 1, false, true});
  }
  b.rate = p.number_or("rate", 0.0, Range::positive());
  b.start = p.number_or("start", 0.0, Range::non_negative());
  if (b.rate > 0 && p.has("count")) throw InputError(p.where("count") + ": a poured batch ('rate') is given by 'mass'");
  const bool by_count = p.has("count"), by_mass = p.has("mass");
  if (by_count == by_mass) {
    throw InputError(p.where(by_count ? "count" : "mass") + ": give exactly one of 'count' or 'mass'");
  }
  if (by_count) b.batch.count = static_cast<std::uint64_t>(p.integer("count", 1, 100'000'000));
  if (by_mass) b.batch.mass = p.number("mass", Range::positive());
  YamlMap region = p.map("region");
  b.batch.region_min = region.vec3("min");
  b.batch.region_max = region.vec3("max");
  region.finish();
  b.batch.velocity = p.vec3_or("velocity", {});
  p.finish();
  return b;
}

}  // namespace

Scenario load_scenario(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  Scenario s;
  s.file = file;
  s.name = root.string("name");
  s.seed = static_cast<std::uint64_t>(root.integer_or("seed", 1, 0, std::numeric_limits<long>::max()));
  s.materials_file = resolve_beside(file, root.string("materials"));
  s.settings.scale_factor = root.number_or("scale_factor", 1.0, {1, 100, false, false});
  s.settings.gravity = root.vec3_or("gravity", {0, 0, -9.81});

  if (auto c = root.optional_map("contact")) {
    s.settings.rolling.model = rolling_model_from_name(c->choice_or("rolling", "constant_torque", rolling_model_names()));
    s.settings.rolling.epsd_stiffness_factor = c->number_or("epsd_stiffness_factor", 2.25, Range::positive());
    s.settings.rolling.epsd_damping_ratio = c->number_or("epsd_damping_ratio", 0.3, Range::non_negative());
    s.settings.max_overlap_ratio = c->number_or("max_overlap", 0.3, {0, 1, true, false});
    c->finish();
  }

  YamlMap t = root.map("time");
  s.end_time = t.number("end", Range::positive());
  s.settings.time_step = t.number_or("step", 0.0, Range::non_negative());
  s.settings.time_step_fraction = t.number_or("step_fraction", 0.2, {0, 1, true, false});
  s.settings.skin = t.number_or("skin", 0.0, Range::non_negative());
  s.settings.list_frame = t.choice_or("list_frame", "auto", {"auto", "world"}) == "world"
                              ? SimulationSettings::ListFrameChoice::world
                              : SimulationSettings::ListFrameChoice::automatic;
  s.pour_interval = t.number_or("pour_interval", 0.01, Range::positive());
  s.settle_kinetic_energy = t.number_or("settle_kinetic_energy", 0.0, Range::non_negative());
  s.settings.stability_interval = static_cast<int>(t.integer_or("stability_interval", 20, 0, 1000000));  // 0: never
  // The step kept below a stability margin, the input's step its ceiling (dem/step_control.hpp).
  StepControl& control = s.settings.step_control;
  control.mode = t.choice_or("step_control", "fixed", {"fixed", "stability"}) == "stability" ? StepControl::Mode::stability
                                                                                            : StepControl::Mode::fixed;
  control.target_margin = t.number_or("step_margin", control.target_margin, {0, 1, true, true});
  control.pour_interval = static_cast<int>(t.integer_or("step_control_pour_interval", control.pour_interval, 1, 1000000));
  if (control.mode == StepControl::Mode::stability && s.settings.stability_interval == 0) {
    throw InputError(t.where("step_control") +
                     ": 'stability' needs the stability check, but time.stability_interval is 0; set it to 1 or more "
                     "(default 20)");
  }
  for (const char* key : {"step_margin", "step_control_pour_interval"}) {
    if (control.mode == StepControl::Mode::fixed && t.has(key)) {
      throw InputError(t.where(key) + ": only read with time.step_control: stability");
    }
  }
  t.finish();

  if (root.has("walls")) {
    for (YamlMap& w : root.list_of_maps("walls")) s.walls.push_back(parse_wall(w, s.end_time));
  }
  for (YamlMap& p : root.list_of_maps("particles")) s.particles.push_back(parse_batch(p, s.settings.scale_factor));

  YamlMap out = root.map("output");
  s.output_directory = out.string("directory");
  s.snapshot_interval = out.number_or("snapshot_interval", 0.0, Range::non_negative());
  s.progress_interval = out.number_or("progress_interval", 5.0, Range::positive());
  s.checkpoint_interval = out.number_or("checkpoint_interval", 600.0, Range::positive());
  out.finish();
  root.finish();
  return s;
}

namespace {

/// The shortest decimal that reads back as the same double (0.2, not 0.20000000000000001).
std::string exact(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}
std::string exact(const Vec3& v) { return "[" + exact(v.x) + ", " + exact(v.y) + ", " + exact(v.z) + "]"; }
std::string exact(const Quat& q) {
  return "[" + exact(q.w) + ", " + exact(q.x) + ", " + exact(q.y) + ", " + exact(q.z) + "]";
}

/// FNV-1a over the bytes of a few arrays: a short, exact stand-in for a mesh or a shape in the
/// fingerprint (changing one coordinate in its last bit changes it).
class Fnv1a {
 public:
  template <class T>
  void add(const std::vector<T>& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t k = 0; k < v.size() * sizeof(T); ++k) h_ = (h_ ^ p[k]) * 0x100000001b3ULL;
  }
  std::string hex() const {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h_));
    return buf;
  }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace

std::vector<std::string> scenario_fingerprint(const Scenario& s) {
  std::vector<std::string> f;
  auto line = [&](const std::string& key, const std::string& value) { f.push_back(key + ": " + value); };
  line("seed", std::to_string(s.seed));
  const MaterialTable mt = MaterialTable::load(s.materials_file);
  for (int a = 0; a < mt.size(); ++a) {
    line("materials." + mt[a].name,
         exact(mt[a].density) + " kg/m^3, G " + exact(mt[a].shear_modulus) + " Pa, nu " + exact(mt[a].poisson_ratio));
    for (int b = a; b < mt.size(); ++b) {
      if (!mt.has_pair(a, b)) continue;
      const PairProperties& p = mt.pair(a, b);
      line("pairs." + mt[a].name + "-" + mt[b].name, "e " + exact(p.restitution) + ", mu " + exact(p.friction) +
                                                         ", mu_r " + exact(p.rolling_friction));
    }
  }
  const SimulationSettings& st = s.settings;
  line("scale_factor", exact(st.scale_factor));
  line("gravity", exact(st.gravity));
  line("contact.rolling", rolling_model_names()[static_cast<int>(st.rolling.model)]);
  line("contact.epsd_stiffness_factor", exact(st.rolling.epsd_stiffness_factor));
  line("contact.epsd_damping_ratio", exact(st.rolling.epsd_damping_ratio));
  line("contact.max_overlap", exact(st.max_overlap_ratio));
  line("time.step", exact(st.time_step));
  line("time.step_fraction", exact(st.time_step_fraction));
  line("time.skin", exact(st.skin));
  // (Only where it is not the default, so that states written before the key existed still match.)
  if (st.list_frame == SimulationSettings::ListFrameChoice::world) line("time.list_frame", "world");
  line("time.pour_interval", exact(s.pour_interval));
  line("time.stability_interval", std::to_string(st.stability_interval));
  if (st.step_control.mode == StepControl::Mode::stability) {  // (only then: as list_frame above)
    line("time.step_control", "stability");
    line("time.step_margin", exact(st.step_control.target_margin));
    line("time.step_control_pour_interval", std::to_string(st.step_control.pour_interval));
  }
  // Motions are compared through where they put the wall at these times (s): spread over the
  // scales of a shaking run, and not round numbers, so that phase shifts and delays show.
  static const double kSampleTimes[] = {0, 0.0123, 0.137, 0.71, 1.93, 4.37, 11.7, 63.1, 301.7, 1811.3, 86400.7};
  for (std::size_t w = 0; w < s.walls.size(); ++w) {
    const WallSpec& ws = s.walls[w];
    const std::string key = "walls[" + std::to_string(w) + "]";
    line(key + ".name", ws.name);
    line(key + ".material", ws.material);
    if (const auto* mesh = dynamic_cast<const MeshGeometry*>(ws.geometry.get())) {
      Fnv1a h;
      h.add(mesh->mesh().vertices);
      h.add(mesh->mesh().triangles);
      line(key + ".geometry", "mesh of " + std::to_string(mesh->mesh().triangles.size()) + " triangles, hash " + h.hex());
    } else {
      line(key + ".geometry", ws.geometry->describe());
    }
    line(key + ".pose", exact(ws.pose.origin) + " " + exact(ws.pose.orientation));
    if (ws.motion.profile) {
      line(key + ".pivot", exact(ws.motion.pivot));
      for (double t : kSampleTimes) {
        const RigidMotionState m = ws.motion.profile->at(t);
        line(key + ".motion(" + exact(t) + ")", exact(m.rotation) + " " + exact(m.displacement) + " " +
                                                    exact(m.angular_velocity) + " " + exact(m.velocity));
      }
    }
  }
  for (std::size_t k = 0; k < s.particles.size(); ++k) {
    const BatchSpec& b = s.particles[k];
    const ParticleBatch& p = b.batch;
    const std::string key = "particles[" + std::to_string(k) + "]";
    line(key + ".material", b.material);
    if (p.shape) {
      Fnv1a h;
      h.add(p.shape->spheres);
      line(key + ".shape", p.shape->name + " (" + std::to_string(p.shape->spheres.size()) + " spheres, hash " + h.hex() +
                               "), particle_mass " + exact(b.particle_mass));
    } else {
      line(key + ".diameter", exact(p.diameter) + " +- " + exact(p.diameter_spread));
    }
    line(key + ".amount", p.count > 0 ? std::to_string(p.count) + " particles" : exact(p.mass) + " kg");
    line(key + ".region", exact(p.region_min) + " to " + exact(p.region_max));
    line(key + ".velocity", exact(p.velocity));
    line(key + ".rate", exact(b.rate) + " kg/s from " + exact(b.start) + " s");
  }
  return f;
}

namespace {

/// Smallest component radius a batch can produce.
double smallest_radius(const ParticleBatch& b) {
  if (!b.shape) return 0.5 * b.diameter * (1 - b.diameter_spread);
  double r = 1e300;
  for (const auto& c : b.shape->spheres) r = std::min(r, c.radius);
  return r;
}

}  // namespace

BuiltScenario build(const Scenario& s, bool place_particles) {
  MaterialTable materials = MaterialTable::load(s.materials_file);
  SimulationSettings settings = s.settings;
  bool pours = false;
  for (const BatchSpec& b : s.particles) pours = pours || b.rate > 0;
  if (pours && settings.skin == 0) {
    // Like the time step, the largest adaptive Verlet skin must suit particles that arrive later
    // (0.2 x the largest radius, as a build would choose with every particle present; before the
    // first arrivals there is no radius to take it from).
    double r_max = 0;
    for (const BatchSpec& b : s.particles) {
      if (!b.batch.shape) r_max = std::max(r_max, 0.5 * b.batch.diameter * (1 + b.batch.diameter_spread));
      else
        for (const auto& c : b.batch.shape->spheres) r_max = std::max(r_max, c.radius);
    }
    settings.skin_max = 0.2 * r_max;
  }
  if (pours && settings.time_step == 0) {
    double t = 1e300;
    for (const BatchSpec& b : s.particles) {
      t = std::min(t, rayleigh_time(smallest_radius(b.batch), materials[materials.index(b.material, b.batch.label)]));
    }
    settings.time_step = settings.time_step_fraction * t;
    settings.time_step_note = "automatic over all batches, poured ones included";
  }
  BuiltScenario out;
  out.sim = std::make_unique<Simulation>(materials, settings);
  out.rng = Random(s.seed);
  for (const WallSpec& w : s.walls) {
    out.sim->add_wall(w.name, w.geometry, materials.index(w.material, s.file + ": wall '" + w.name + "'"), w.pose);
    if (w.motion.profile) out.sim->walls().back().set_motion(w.motion);
  }
  for (const BatchSpec& b : s.particles) {
    ParticleBatch batch = b.batch;
    batch.material = materials.index(b.material, b.batch.label);
    if (b.particle_mass > 0) batch.density = b.particle_mass / union_mass_properties(batch.shape->spheres).volume;
    if (b.rate > 0) {
      out.pours.emplace_back(batch, b.rate, b.start, s.pour_interval);
      continue;
    }
    if (!place_particles) continue;
    const std::size_t first = out.sim->particles().size();
    const InsertionReport r = insert_particles(*out.sim, batch, out.rng);
    require_clear_of_walls(*out.sim, first, b.batch.label + ".region");
    std::ostringstream line;
    line << b.batch.label << ": placed " << r.placed << (batch.shape ? " " + batch.shape->name + " clumps" : " spheres")
         << ", " << r.mass << " kg, density " << (batch.density > 0 ? batch.density : materials[batch.material].density)
         << " kg/m^3" << (b.particle_mass > 0 ? " (set from particle_mass " + std::to_string(b.particle_mass) + " kg)" : "");
    out.report.push_back(line.str());
  }
  return out;
}

void BuiltScenario::advance(std::uint64_t steps) {
  if (!pouring()) {  // (a pour done inserts nothing more: its update would only look at the clock)
    sim->run_steps(steps);
    return;
  }
  for (Pour& p : pours) p.update(*sim, rng);
  sim->step();
  // The step control checks more often while particles land (StepControl::pour_interval); not on a
  // step whose regular check has just run.
  const StepControl& control = sim->settings().step_control;
  const auto every = static_cast<std::uint64_t>(control.pour_interval);
  if (control.mode == StepControl::Mode::stability && sim->steps() % every == 0 &&
      sim->steps() % static_cast<std::uint64_t>(sim->settings().stability_interval) != 0) {
    sim->check_and_control_step(control.pour_interval);
  }
}

bool BuiltScenario::pouring() const {
  for (const Pour& p : pours) {
    if (!p.done()) return true;
  }
  return false;
}

std::vector<std::string> BuiltScenario::pour_report() const {
  std::vector<std::string> lines;
  for (const Pour& p : pours) {
    std::ostringstream line;
    line << p.batch().label << ": poured " << p.poured_count() << " particles, " << p.poured_mass() << " of "
         << p.batch().mass << " kg" << (p.done() ? "" : " (not finished)");
    if (p.waits() > 0) line << "; the region was full " << p.waits() << " times and the pour waited for room";
    lines.push_back(line.str());
  }
  return lines;
}

}  // namespace grainscale::dem
