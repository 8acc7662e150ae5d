#include "dem/parallel.hpp"
#include "dem/simulation.hpp"
#include "dem/adaptive_skin.hpp"
#include "dem/boundary_lines.hpp"
#include "dem/prefetch.hpp"
#include "dem/rotation_batch.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "dem/input_error.hpp"
#include "dem/rigid_rotation.hpp"
#include "dem/time_step.hpp"

namespace grainscale::dem {

Simulation::Simulation(MaterialTable materials, SimulationSettings settings)
    : materials_(std::move(materials)), settings_(settings) {}

std::uint64_t Simulation::add_body(double mass, const Vec3& inertia, const Vec3& x, const Quat& q, const Vec3& v,
                                   const Vec3& omega, int shape) {
  // Made later, the new body's omega would be made from its L. The bodies' own arrays hold their
  // state again until the next indexing (index_spheres_by_body).
  update_bodies();
  spheres_hold_bodies_ = false;
  Bodies& b = bodies_;
  const std::uint64_t id = b.size();
  b.id.push_back(id);
  b.shape.push_back(shape);
  b.mass.push_back(mass);
  b.inv_mass.push_back(1.0 / mass);
  b.inertia.push_back(inertia);
  b.x.push_back(x);
  b.v.push_back(v);
  b.q.push_back(q);
  const Vec3 wb = to_body(q, omega);
  b.L.push_back(rotate(q, {inertia.x * wb.x, inertia.y * wb.y, inertia.z * wb.z}));
  b.omega.push_back(omega);
  // Added to a running simulation: it was placed clear of everything, so its weight is its whole
  // load until the next force computation; the neighbour list notices the new count and rebuilds,
  // keeping every existing contact history. Before the first step, setup() does it all.
  b.force.push_back(ready_ ? mass * settings_.gravity : Vec3{});
  b.torque.push_back({});
  return id;
}

void Simulation::check_step_for(int material, double radius) const {
  if (!ready_ || settings_.time_step > 0) return;
  const double needed = settings_.time_step_fraction * dem::rayleigh_time(radius, materials_[material]);
  if (needed < dt_ceiling_ * (1 - 1e-12)) {  // (the step control may raise the step back up to the ceiling)
    std::ostringstream m;
    m << "a " << materials_[material].name << " sphere of radius " << radius << " m added at t = " << time_
      << " s needs a time step of " << needed << " s, smaller than the running " << dt_ceiling_
      << " s; set time.step, or include the smallest particle before the first step";
    throw InputError(m.str());
  }
}

std::uint64_t Simulation::add_sphere(int material, double radius, const Vec3& x, const Vec3& v, const Vec3& omega) {
  if (material < 0 || material >= materials_.size()) throw InputError("add_sphere: material index out of range");
  if (!(radius > 0) || !std::isfinite(radius)) throw InputError("add_sphere: radius must be positive and finite");
  const double m = materials_[material].density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double inertia = 0.4 * m * radius * radius;
  check_step_for(material, radius);
  const std::uint64_t body = add_body(m, {inertia, inertia, inertia}, x, {}, v, omega, -1);
  const std::size_t s = particles_.add_component(next_sphere_id_++, static_cast<std::uint32_t>(body), material, radius, {},
                                                 m, inertia, m, x);
  particles_.v[s] = v;
  particles_.omega[s] = omega;
  return body;
}

std::uint64_t Simulation::add_clump(const Shape& shape, int material, double density, const Vec3& x, const Quat& orientation,
                                    const Vec3& v, const Vec3& omega) {
  if (material < 0 || material >= materials_.size()) throw InputError("add_clump: material index out of range");
  if (!(density > 0) || !std::isfinite(density)) throw InputError("add_clump: density must be positive and finite");
  int shape_index = -1;
  for (std::size_t k = 0; k < shape_names_.size(); ++k) {
    if (shape_names_[k] == shape.name) shape_index = static_cast<int>(k);
  }
  if (shape_index < 0) {
    shape_names_.push_back(shape.name);
    shape_index = static_cast<int>(shape_names_.size()) - 1;
  }
  for (const auto& c : shape.spheres) check_step_for(material, c.radius);
  const MassProperties& mp = mass_properties_of(shape);
  const double mass = density * mp.volume;
  const Vec3 inertia = density * mp.principal_moments;
  // Body frame = principal frame; the user's orientation turns the shape file's frame into the world.
  const Quat q = normalized(orientation * mp.principal_orientation);
  const std::uint64_t body = add_body(mass, inertia, x, q, v, omega, shape_index);
  // Each sphere stands for a share of the mass proportional to its own volume (overlaps shared).
  double sum_r3 = 0;
  for (const auto& c : shape.spheres) sum_r3 += c.radius * c.radius * c.radius;
  for (const auto& c : shape.spheres) {
    const Vec3 off = to_body(mp.principal_orientation, c.center - mp.centroid);
    particles_.add_component(next_sphere_id_++, static_cast<std::uint32_t>(body), material, c.radius, off, mass,
                             inertia.x, mass * c.radius * c.radius * c.radius / sum_r3, x + rotate(q, off));
  }
  return body;
}

const MassProperties& Simulation::mass_properties_of(const Shape& shape) {
  // A pour adds thousands of clumps of a few shapes; the union integral takes about a millisecond.
  auto same = [](const std::vector<SphereComponent>& a, const std::vector<SphereComponent>& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const SphereComponent& p, const SphereComponent& q) {
      return p.radius == q.radius && p.center.x == q.center.x && p.center.y == q.center.y && p.center.z == q.center.z;
    });
  };
  for (const auto& [spheres, mp] : mass_cache_) {
    if (same(spheres, shape.spheres)) return mp;
  }
  mass_cache_.emplace_back(shape.spheres, union_mass_properties(shape.spheres));
  return mass_cache_.back().second;
}

void Simulation::add_wall(std::string name, std::shared_ptr<const WallGeometry> geometry, int material,
                          const WallPose& pose) {
  if (material < 0 || material >= materials_.size()) throw InputError("wall '" + name + "': material index out of range");
  // Wall names key the wall's record in every snapshot (/walls/<name>), so they must be usable there.
  if (name.empty() || name == "." || name.find('/') != std::string::npos) {
    throw InputError("wall name '" + name + "' is not allowed: it must be non-empty, not '.', and without '/'");
  }
  for (const Wall& w : walls_) {
    if (w.name() == name) throw InputError("two walls are named '" + name + "'; wall names must be unique");
  }
  walls_.emplace_back(std::move(name), std::move(geometry), material, pose);
  ready_ = false;
}

double Simulation::rayleigh_time() const {
  double t = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    t = std::min(t, dem::rayleigh_time(particles_.radius[i], materials_[particles_.material[i]]));
  }
  return t;
}

std::string Simulation::time_step_report() const {
  std::ostringstream s;
  s << "time step " << dt_ << " s";
  if (particles_.size() > 0) {  // (a scenario that only pours starts empty)
    s << " = " << dt_ / rayleigh_time() * 100 << " % of the Rayleigh time " << rayleigh_time() << " s";
  }
  s << " ("
    << (!settings_.time_step_note.empty() ? settings_.time_step_note
                                          : (settings_.time_step > 0 ? "set in the input" : "automatic"))
    << ")";
  if (settings_.step_control.mode == StepControl::Mode::stability) {
    s << "; step control: kept below a stability margin of " << settings_.step_control.target_margin << ", at most "
      << dt_ceiling_ << " s (dem/step_control.hpp)";
  }
  return s.str();
}

void Simulation::check_pairs_in_use(const Particles& p) const {
  // Every material pair that can meet must have interaction properties.
  std::set<int> used(p.material.begin(), p.material.end());
  for (int a : used) {
    for (int b : used) materials_.pair(a, b);
    for (const Wall& w : walls_) materials_.pair(a, w.material());
  }
  for (int m : used) {
    if (!std::isfinite(materials_[m].shear_modulus)) {
      throw InputError("material '" + materials_[m].name +
                       "' is rigid (infinite shear modulus) and cannot be used for particles");
    }
  }
}

namespace {

void check_step_control(const SimulationSettings& s) {
  if (s.step_control.mode == StepControl::Mode::fixed) return;
  if (!(s.step_control.target_margin > 0 && s.step_control.target_margin < 1)) {
    throw InputError("the step control's target margin must lie in (0, 1), not " +
                     std::to_string(s.step_control.target_margin));
  }
  if (s.stability_interval <= 0) {
    throw InputError("the step control needs the stability check: a stability interval of 1 step or more, not " +
                     std::to_string(s.stability_interval));
  }
  if (s.step_control.pour_interval <= 0) {
    throw InputError("the step control's interval while pouring must be 1 step or more, not " +
                     std::to_string(s.step_control.pour_interval));
  }
}

}  // namespace

double Simulation::input_time_step() const {
  return settings_.time_step > 0 ? settings_.time_step : settings_.time_step_fraction * rayleigh_time();
}

void Simulation::setup() {
  check_pairs_in_use(particles_);
  if (!(settings_.time_step > 0) && particles_.size() == 0) {
    throw InputError("cannot choose a time step automatically without particles");
  }
  dt_ = input_time_step();
  check_step_control(settings_);
  dt_ceiling_ = dt_;
  lowest_dt_ = dt_;
  dt_changes_ = 0;
  forces_.setup(materials_, walls_, settings_.rolling);
  for (Wall& w : walls_) w.move_to(time_);
  move_spheres_with_bodies();
  rebuild(choose_skins());
  compute_forces(0);
  ready_ = true;
}

namespace {

/// Counting sort of sphere slots by body; within a body, slot order (fixed for a given state).
void index_spheres(const Particles& p, Bodies& b, std::vector<std::uint32_t>& fill) {
  const std::size_t nb = b.size(), ns = p.size();
  b.sphere_start.assign(nb + 1, 0);
  for (std::size_t s = 0; s < ns; ++s) ++b.sphere_start[p.body[s] + 1];
  for (std::size_t k = 0; k < nb; ++k) b.sphere_start[k + 1] += b.sphere_start[k];
  b.sphere_slot.resize(ns);
  fill.assign(b.sphere_start.begin(), b.sphere_start.end() - 1);
  for (std::size_t s = 0; s < ns; ++s) b.sphere_slot[fill[p.body[s]]++] = static_cast<std::uint32_t>(s);
}

/// Throw std::invalid_argument unless every array of `p` has the length of `p.id`, and likewise for `b`.
void check_lengths(const Particles& p, const Bodies& b) {
  const std::size_t n = p.size(), nb = b.size();
  auto same = [](std::size_t got, std::size_t want, const char* what) {
    if (got != want) {
      throw std::invalid_argument(std::string(what) + " has " + std::to_string(got) + " entries, expected " +
                                  std::to_string(want));
    }
  };
  same(p.material.size(), n, "particles.material");
  same(p.body.size(), n, "particles.body");
  same(p.offset.size(), n, "particles.offset");
  same(p.radius.size(), n, "particles.radius");
  same(p.mass.size(), n, "particles.mass");
  same(p.inertia.size(), n, "particles.inertia");
  same(p.mass_share.size(), n, "particles.mass_share");
  same(p.x.size(), n, "particles.x");
  same(p.v.size(), n, "particles.v");
  same(p.omega.size(), n, "particles.omega");
  same(p.force.size(), n, "particles.force");
  same(p.torque.size(), n, "particles.torque");
  same(p.q.size(), n, "particles.q");
  same(p.x_at_build.size(), n, "particles.x_at_build");
  same(b.shape.size(), nb, "bodies.shape");
  same(b.mass.size(), nb, "bodies.mass");
  same(b.inv_mass.size(), nb, "bodies.inv_mass");
  same(b.inertia.size(), nb, "bodies.inertia");
  same(b.x.size(), nb, "bodies.x");
  same(b.v.size(), nb, "bodies.v");
  same(b.L.size(), nb, "bodies.L");
  same(b.omega.size(), nb, "bodies.omega");
  same(b.q.size(), nb, "bodies.q");
  same(b.force.size(), nb, "bodies.force");
  same(b.torque.size(), nb, "bodies.torque");
}

}  // namespace

void Simulation::restore(SimulationState&& s) {
  // Check everything first, so that a bad state leaves this simulation as it was.
  Particles& p = s.particles;
  Bodies& b = s.bodies;
  check_lengths(p, b);
  const std::size_t n = p.size(), nb = b.size();
  auto bad = [](const std::string& why) { throw std::invalid_argument(why); };
  if (n > std::numeric_limits<std::uint32_t>::max() - 1 || nb > std::numeric_limits<std::uint32_t>::max()) {
    bad("too many particles or bodies for 32-bit slot indices");
  }
  if (!(s.dt > 0) || !std::isfinite(s.dt)) bad("the time step must be positive and finite");
  if (!std::isfinite(s.time)) bad("the time must be finite");
  std::vector<bool> id_seen(nb, false);  // bodies are renumbered with their spheres: any order of 0 .. nb-1
  for (std::size_t k = 0; k < nb; ++k) {
    if (b.id[k] >= nb || id_seen[b.id[k]]) {
      bad("bodies.id must hold each of 0 .. " + std::to_string(nb) + "-1 once (body " + std::to_string(k) +
          " has id " + std::to_string(b.id[k]) + ")");
    }
    id_seen[b.id[k]] = true;
    if (b.shape[k] < -1 || b.shape[k] >= static_cast<std::int64_t>(s.shape_names.size())) {
      bad("body " + std::to_string(k) + " has shape index " + std::to_string(b.shape[k]) + " outside [-1, " +
          std::to_string(s.shape_names.size()) + ")");
    }
  }
  // Finite numbers only: a checkpoint is never written from a non-finite state, and positions feed
  // integer cell indices (a NaN there is undefined behaviour, not just a wrong answer).
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_finite(p.x[i]) || !is_finite(p.x_at_build[i]) || !is_finite(p.v[i]) || !is_finite(p.offset[i]) ||
        !std::isfinite(p.radius[i]) || !(p.radius[i] > 0)) {
      bad("particle slot " + std::to_string(i) + " has a non-finite position, velocity or offset, or a bad radius");
    }
  }
  for (std::size_t k = 0; k < nb; ++k) {
    const Vec3 I = b.inertia[k];
    if (!is_finite(b.x[k]) || !is_finite(b.v[k]) || !is_finite(b.L[k]) || !is_finite(b.force[k]) ||
        !is_finite(b.torque[k]) || !is_unit(b.q[k]) || !(b.mass[k] > 0) || !std::isfinite(b.mass[k]) ||
        b.inv_mass[k] != 1.0 / b.mass[k] || !(I.x > 0 && I.y > 0 && I.z > 0) || !is_finite(I)) {
      bad("body " + std::to_string(k) +
          " has a non-finite state, an orientation that is not a unit quaternion, or a mass or inertia that is not "
          "positive");
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!(p.mass[i] > 0) || !std::isfinite(p.mass[i]) || !(p.inertia[i] > 0) || !std::isfinite(p.inertia[i]) ||
        !(p.mass_share[i] >= 0) || !std::isfinite(p.mass_share[i])) {
      bad("particle slot " + std::to_string(i) + " has a mass or inertia that is not positive and finite");
    }
  }
  std::vector<std::uint64_t> ids(p.id);
  std::sort(ids.begin(), ids.end());
  if (std::adjacent_find(ids.begin(), ids.end()) != ids.end()) bad("two particles have the same id");
  if (n > 0 && ids.back() >= s.next_sphere_id) bad("a particle id is not below the next id to be given");
  for (std::size_t i = 0; i < n; ++i) {
    if (p.material[i] < 0 || p.material[i] >= materials_.size()) {
      bad("particle slot " + std::to_string(i) + " has material index " + std::to_string(p.material[i]) +
          " outside [0, " + std::to_string(materials_.size()) + ")");
    }
    if (p.body[i] >= nb) bad("particle slot " + std::to_string(i) + " belongs to no body");
  }
  check_pairs_in_use(p);
  // (Wall contacts and the neighbour list may cover fewer particles: those added since the last step.)
  if (s.wall_count.size() > n) bad("more wall contact counts than particles");
  // The per-body sphere index is a function of the slot order: rebuild it, and refuse a state whose
  // stored index disagrees (it would not have come from a Simulation).
  std::vector<std::uint32_t> saved_start, saved_slot, fill;
  saved_start.swap(b.sphere_start);
  saved_slot.swap(b.sphere_slot);
  index_spheres(p, b, fill);
  if ((!saved_start.empty() && saved_start != b.sphere_start) || (!saved_slot.empty() && saved_slot != b.sphere_slot)) {
    bad("bodies.sphere_start/sphere_slot do not match the slot order of the particles");
  }
  // Validate the neighbour list and wall contacts in scratch objects before touching ours.
  NeighborList nl;
  nl.restore(p, s.skin, std::move(s.neighbor_skin), std::move(s.neighbor_start), std::move(s.neighbor_partner),
             std::move(s.neighbor_history), s.neighbor_builds);
  if (s.neighbor_frame_wall < -1) bad("the neighbour list's frame wall must be -1 (the world) or a wall's index");
  if (s.neighbor_frame_wall >= 0) {
    // Any rigid frame keeps the list exact (dem/list_frame.hpp), so that of a wall that has no
    // motion under this scenario would do; a wall that is not there would not.
    if (static_cast<std::size_t>(s.neighbor_frame_wall) >= walls_.size()) {
      bad("the neighbour list is measured in the frame of wall " + std::to_string(s.neighbor_frame_wall) +
          ", but there are " + std::to_string(walls_.size()) + " walls");
    }
    const WallPose& at_build = s.neighbor_frame_at_build;
    if (!is_finite(at_build.origin) || !is_unit(at_build.orientation)) {
      bad("the neighbour list's frame at its build must have a finite origin and a unit orientation");
    }
    nl.set_frame({s.neighbor_frame_wall, at_build});
  }
  ForceField ff;
  ff.restore_wall_contacts(s.wall_count, s.wall_slots, walls_.size());

  // Commit (nothing below throws but forces_.setup, which depends only on materials and walls).
  forces_.setup(materials_, walls_, settings_.rolling);
  forces_.restore_wall_contacts(s.wall_count, s.wall_slots, walls_.size());
  neighbors_ = std::move(nl);
  particles_ = std::move(p);
  sphere_state_lags_ = false;
  bodies_ = std::move(b);
  body_omega_lags_ = false;
  spheres_hold_bodies_ = false;  // the bodies' arrays hold their state (index_spheres_by_body decides anew)
  body_copy_lags_ = false;
  shape_names_ = std::move(s.shape_names);
  time_ = s.time;
  dt_ = s.dt;
  // A fixed step goes on as the state has it; a controlled one may rise back to the input's ceiling
  // (as setup() chose it: the same particles, the same settings).
  // (A state without particles has no Rayleigh time: its own step is the ceiling.)
  dt_ceiling_ = settings_.step_control.mode == StepControl::Mode::fixed || particles_.size() == 0 ? dt_ : input_time_step();
  lowest_dt_ = s.lowest_dt > 0 ? s.lowest_dt : dt_;
  dt_changes_ = s.dt_changes;
  skin_ = s.skin;
  steps_ = s.steps;
  next_sphere_id_ = s.next_sphere_id;
  diag_ = s.diagnostics;
  stability_ = s.stability;
  worst_stability_ = s.worst_stability;
  moved2_ = 0;  // recomputed by the next step's drift before it is used
  // A state written before bodies were renumbered with their spheres has them in id order; the order
  // changes no result (dem/bodies.hpp), so it is set here rather than at the next list build.
  renumber_bodies();
  index_spheres_by_body();
  for (Wall& w : walls_) w.move_to(time_);
  ready_ = true;
}

int Simulation::container_wall() const {
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    if (walls_[w].moving()) return static_cast<int>(w);
  }
  return -1;
}

FrameShift Simulation::frame_shift_at(double t) const {
  const ListFrame& f = neighbors_.frame();
  return f.in_wall() ? f.shift_to(walls_[f.wall].pose_at(t)) : FrameShift{};
}

Simulation::SkinChoice Simulation::choose_skins() const {
  const Particles& p = particles_;
  const std::size_t n = p.size();
  // The list's frame (dem/list_frame.hpp): the container's where the spheres' common speed (below)
  // is lower there than in the world, so that a bed carried by its box lasts a list the longer.
  const int wall = settings_.list_frame == SimulationSettings::ListFrameChoice::world ? -1 : container_wall();
  if (settings_.skin > 0 && wall < 0) return {settings_.skin, settings_.skin, -1};
  // (The velocities of spheres that follow bodies are made for readers: follow_one.)
  if (sphere_state_lags_) update_sphere_state();
  // Each sphere's speed, in the world and relative to the container (strays with slack left out:
  // they may outrun the skin anyway, NeighborList::slack2; -1 marks them), and the largest radius
  // present for the default bound.
  const double* slack = neighbors_.slack2().data();
  const std::size_t slack_n = neighbors_.slack2().size();
  const WallPose* container = wall >= 0 ? &walls_[wall].pose() : nullptr;
  speed2_.resize(n);
  if (container) frame_speed2_.resize(n);
  double r_max = 0;
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static) reduction(max : r_max)
  for (std::size_t s = 0; s < n; ++s) {
    r_max = std::max(r_max, p.radius[s]);
    const bool stray = s < slack_n && slack[s] > 0;
    speed2_[s] = stray ? -1.0 : norm2(p.v[s]);
    if (container) frame_speed2_[s] = stray ? -1.0 : norm2(p.v[s] - container->surface_velocity(p.x[s]));
  }
  const double skin_max = settings_.skin_max > 0 ? settings_.skin_max : 0.2 * r_max;
  // The common skin follows the speed that all but the fastest AdaptiveSkin::kFastShare of the
  // spheres keep under; those faster get their own (the same bits as one skin for all where even the
  // fastest's skin is the floor). NaN if some speed is not finite.
  auto common_speed2 = [&](const std::vector<double>& speed2) {
    skin_scratch_.clear();
    bool finite = true;
    for (std::size_t s = 0; s < n; ++s) {
      finite = finite && std::isfinite(speed2[s]);
      if (speed2[s] >= 0) skin_scratch_.push_back(speed2[s]);
    }
    if (!finite) return std::numeric_limits<double>::quiet_NaN();
    if (skin_scratch_.empty()) return 0.0;
    const std::size_t m = skin_scratch_.size();
    const std::size_t faster = static_cast<std::size_t>(AdaptiveSkin::kFastShare * static_cast<double>(m - 1));
    const auto k = skin_scratch_.begin() + static_cast<std::ptrdiff_t>(m - 1 - faster);
    std::nth_element(skin_scratch_.begin(), k, skin_scratch_.end());
    return *k;
  };
  double v2_common = common_speed2(speed2_);
  int frame_wall = -1;
  if (container) {
    const double v2_frame = common_speed2(frame_speed2_);
    if (v2_frame < v2_common) {  // (false for NaN: a blown-up state keeps to the world)
      v2_common = v2_frame;
      frame_wall = wall;
      speed2_.swap(frame_speed2_);
    }
  }
  if (settings_.skin > 0) return {settings_.skin, settings_.skin, frame_wall};
  // (A blown-up state's velocities may not be finite: keep to the bound, the sort reports it.)
  if (!std::isfinite(v2_common)) return {skin_max, skin_max, frame_wall};
  const double common = AdaptiveSkin::choose(std::sqrt(v2_common), dt_, skin_max);
  own_skin_.resize(n);
  double largest = common;
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static) reduction(max : largest)
  for (std::size_t s = 0; s < n; ++s) {
    own_skin_[s] = speed2_[s] > v2_common ? AdaptiveSkin::choose_own(std::sqrt(speed2_[s]), dt_, skin_max) : common;
    largest = std::max(largest, own_skin_[s]);
  }
  return {common, largest, frame_wall};
}

bool Simulation::skin_check_due() const {
  // A fixed skin other than the list's (a state restored under a scenario with another time.skin),
  // or the adaptive skin's regular check.
  return settings_.skin > 0 ? skin_ != settings_.skin : steps_ % AdaptiveSkin::kCheckEvery == 0;
}

std::optional<Simulation::SkinChoice> Simulation::early_rebuild() const {
  if (!skin_check_due()) return std::nullopt;
  const SkinChoice chosen = choose_skins();
  if (settings_.skin > 0) return chosen;
  // The common skin is what most spheres' entries cost (the few faster ones keep theirs to the build).
  if (AdaptiveSkin::shrink(neighbors_.smallest_skin(), chosen.common)) return chosen;
  return std::nullopt;
}

void Simulation::rebuild(const SkinChoice& skins) {
  forces_.resize(particles_.size());  // wall-contact slots for particles added since the last build
  skin_ = skins.largest;
  const std::vector<std::uint32_t>* sorted = nullptr;
  try {
    sorted = &neighbors_.sort_by_cell(particles_, skin_);
  } catch (const std::overflow_error& e) {
    throw BlowUp("t = " + std::to_string(time_) + " s (step " + std::to_string(steps_) + "): " + e.what() +
                 ": the state has blown up (likely causes: a time step far too large, or absurd masses, inertias "
                 "or velocities).");
  }
  const std::vector<std::uint32_t>& order = *sorted;
  renumbering_.assign(order);  // (in a bed at rest it moves ~1 % of the slots: dem/permutation.hpp)
  particles_.permute(renumbering_);
  forces_.permute(renumbering_);
  renumber_bodies();
  if (skins.common == skins.largest) {
    neighbors_.build(particles_, skin_, order);
  } else {
    // The spheres of a skin of their own, in the new order, and the neighbours they may strike
    // before the next build given it too (dem/adaptive_skin.hpp).
    const std::size_t n = particles_.size();
    skin_scratch_.resize(n);
    for (std::size_t k = 0; k < n; ++k) skin_scratch_[k] = own_skin_[order[k]];
    neighbors_.spread_to_adjacent_cells(particles_, skin_scratch_, skins.common, own_skin_);
    neighbors_.build(particles_, own_skin_, order);
  }
  neighbors_.set_frame(skins.frame_wall >= 0 ? ListFrame{skins.frame_wall, walls_[skins.frame_wall].pose()} : ListFrame{});
  index_spheres_by_body();
}

void Simulation::renumber_bodies() {
  // Bodies in the order of their first sphere's slot (dem/bodies.hpp); allocation-free once the
  // scratch vectors have reached the body count.
  Particles& p = particles_;
  const std::size_t nb = bodies_.size(), n = p.size();
  constexpr std::uint32_t kUnset = std::numeric_limits<std::uint32_t>::max();
  body_new_index_.assign(nb, kUnset);
  body_order_.clear();
  for (std::size_t s = 0; s < n; ++s) {
    std::uint32_t& k = body_new_index_[p.body[s]];
    if (k == kUnset) {
      k = static_cast<std::uint32_t>(body_order_.size());
      body_order_.push_back(p.body[s]);
    }
  }
  assert(body_order_.size() == nb);  // every body has a sphere
  body_renumbering_.assign(body_order_);
  bodies_.permute(body_renumbering_);
  for (std::size_t s = 0; s < n; ++s) p.body[s] = body_new_index_[p.body[s]];
}


bool Simulation::loose_spheres_in_order() const {
  const Particles& p = particles_;
  const Bodies& b = bodies_;
  const std::size_t n = p.size();
  if (!settings_.loose_bodies_in_spheres || b.size() != n || !b.indexed(n)) return false;
  for (std::size_t k = 0; k < n; ++k) {
    // (The step reads the sphere's copies of its body's mass and inertia: the same numbers.)
    const Vec3& o = p.offset[k];
    const Vec3& inertia = b.inertia[k];
    if (b.shape[k] != -1 || p.body[k] != k || !(o.x == 0 && o.y == 0 && o.z == 0) || p.mass[k] != b.mass[k] ||
        !(p.inertia[k] == inertia.x && inertia.x == inertia.y && inertia.y == inertia.z)) {
      return false;
    }
  }
  return true;
}

void Simulation::index_spheres_by_body() {
  index_spheres(particles_, bodies_, body_fill_);
  // Where the bodies' state is kept (spheres_hold_bodies_). Taken over by the spheres: theirs made
  // the bodies' (the follow leaves them so already, but for the sign of a zero). Only add_body and
  // restore change the bodies, and both give the state back to the bodies' arrays first, so a bed
  // whose spheres hold it stays one.
  const bool loose = loose_spheres_in_order();
  assert(loose || !spheres_hold_bodies_);
  if (loose && !spheres_hold_bodies_) {
    if (body_omega_lags_) update_body_omega();
    Particles& p = particles_;
    const Bodies& b = bodies_;
    for (std::size_t k = 0; k < b.size(); ++k) p.x[k] = b.x[k], p.v[k] = b.v[k], p.omega[k] = b.omega[k];
    body_copy_lags_ = false;
  }
  spheres_hold_bodies_ = loose;
  // Within a body the slots are ascending (index_spheres), so its first and last are its extent.
  const Bodies& b = bodies_;
  std::size_t span = 0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    span = std::max<std::size_t>(span, b.sphere_slot[b.sphere_start[k + 1] - 1] - b.sphere_slot[b.sphere_start[k]]);
  }
  body_slot_span_ = span;
}

namespace {
/// omega = R I^-1 R^T L; for an isotropic body simply L / I (no rotations needed).
inline Vec3 body_angular_velocity(const Quat& q, const Vec3& L, const Vec3& inertia) {
  if (inertia.x == inertia.y && inertia.y == inertia.z) return (1.0 / inertia.x) * L;
  return angular_velocity(q, L, inertia);
}

/// Sphere s's squared displacement since the last neighbour build to `x`, in the list's frame
/// (`shift`; kInFrame false: the world's), less its slack (follow_one).
template <bool kInFrame>
inline double moved_since_build(const Particles& p, std::size_t s, const Vec3& x, const double* slack, std::size_t slack_n,
                                const FrameShift& shift) {
  const Vec3& at_build = p.x_at_build[s];
  const double moved2 = norm2(x - (kInFrame ? shift.carry(at_build) : at_build));
  return s < slack_n ? moved2 - slack[s] : moved2;
}
/// Sphere s follows body k: x_s = x_b + R(q_b) offset_s. Its velocity and angular velocity are not
/// copied: the force loop makes them from the body's (ForceField::read_motion_from_bodies; the
/// copies were 48 of the 72 bytes this stored per sphere-step), and a reader of the spheres gets them
/// from update_sphere_state. Returns the squared displacement since the last neighbour build in the
/// list's frame (`shift`: where the build's position is now if fixed in that frame), less the
/// sphere's slack if kSlack (slack[s], a stray's: NeighborList::slack2). kInFrame false: the world's
/// frame (`shift` unused), the loop free of the frame's branch (the clump bed's step was 3-5 % slower
/// with the branch inside it; the callers pick once per loop). Component by component, in and out:
/// a Vec3 copied whole (it was `omega_s = omega_b`) is one statement with two memory references,
/// which GCC's vectoriser refuses (follow_span); a Vec3 local stored whole was kept on GCC's stack
/// and copied 16 bytes at a time, and read back, the 16-byte load of two 8-byte stores failed to
/// forward (a third of the sphere loop's samples, nineteenth session).
template <bool kInFrame, bool kSlack>
[[gnu::always_inline]] inline double follow_one(std::size_t s, std::size_t k, const Quat* __restrict q,
                                                const Vec3* __restrict bx, const Vec3* __restrict offset,
                                                const Vec3* __restrict at_build, Vec3* __restrict xs,
                                                const double* __restrict slack, const FrameShift& shift) {
  const Vec3 r = rotate(Quat{q[k].w, q[k].x, q[k].y, q[k].z}, Vec3{offset[s].x, offset[s].y, offset[s].z});
  const double x0 = bx[k].x + r.x, x1 = bx[k].y + r.y, x2 = bx[k].z + r.z;
  xs[s].x = x0, xs[s].y = x1, xs[s].z = x2;
  const Vec3 then{at_build[s].x, at_build[s].y, at_build[s].z};
  const double moved2 = norm2(Vec3{x0, x1, x2} - (kInFrame ? shift.carry(then) : then));
  if constexpr (kSlack) return moved2 - slack[s];
  return moved2;
}
/// The largest moved_since_build over spheres [first, last) where they are, the frame's branch taken once.
inline double moved_spheres(const Particles& p, std::size_t first, std::size_t last, const double* slack,
                            std::size_t slack_n, const FrameShift& shift) {
  double moved2 = 0;
  if (shift.identity) {
    for (std::size_t s = first; s < last; ++s) moved2 = std::max(moved2, moved_since_build<false>(p, s, p.x[s], slack, slack_n, shift));
  } else {
    for (std::size_t s = first; s < last; ++s) moved2 = std::max(moved2, moved_since_build<true>(p, s, p.x[s], slack, slack_n, shift));
  }
  return moved2;
}
/// A body of one sphere at its centre: its force and torque from the sphere's contact sums, as
/// sum_body makes them, by the same operations (the same bits; the lever x_s - x_b is +0).
inline Vec3 lone_sphere_force(const Vec3& contact_force, double mass, const Vec3& gravity) {
  Vec3 f{};
  f += contact_force;
  return f + mass * gravity;
}
inline Vec3 lone_sphere_torque(const Vec3& contact_force, const Vec3& contact_torque) {
  Vec3 t{};
  t += cross(Vec3{}, contact_force) + contact_torque;
  return t;
}
/// A half kick of body k, a sphere at its centre in slot k, in the sphere's v and the body's L, as
/// sum_body and the drift kick a body (the same bits).
inline void kick_lone_sphere(Particles& p, Bodies& b, std::size_t k, double half, const Vec3& gravity) {
  p.v[k] += (half * b.inv_mass[k]) * lone_sphere_force(p.force[k], p.mass[k], gravity);
  b.L[k] += half * lone_sphere_torque(p.force[k], p.torque[k]);
}
constexpr std::size_t kFollowLanes = 8;
/// Spheres [first, last) follow their bodies (follow_one), kFollowLanes at a time, vectorised: the
/// bodies' state loaded by index, element by element, into vector registers (GCC's emulated gather:
/// no gather instruction, which the Downfall microcode makes slow), the spheres' triples read and
/// written interleaved; each lane keeps its own running maximum of moved_since_build in `lane`
/// (the largest is the same number in any order). Not inlined: its arrays are restrict-qualified
/// parameters, which GCC honours in a function of its own; inlined, the vectoriser wanted more
/// run-time alias checks than it allows and left the loop scalar. The bodies' state copied into
/// lane arrays first, as RotationBatch does, stalled: each vector load of the copies waited for the
/// scalar stores it spans to reach the cache (a third of the loop's samples). A sphere at a time,
/// the follow's loop was 14 % of the clump bed's cycles on the Intel VM (perf, 2026-12-07);
/// tests/dem/follow_vectorised.sh checks it stays vectorised. kSlack: [first, last) lies below the
/// slacks' end.
template <bool kInFrame, bool kSlack>
[[gnu::noinline]] void follow_span(std::size_t first, std::size_t last, const std::uint32_t* __restrict body,
                                   const Quat* __restrict q, const Vec3* __restrict bx,
                                   const Vec3* __restrict offset, const Vec3* __restrict at_build,
                                   Vec3* __restrict xs, const double* __restrict slack, const FrameShift& shift,
                                   double* __restrict lane) {
  std::size_t s = first;
  for (; s + kFollowLanes <= last; s += kFollowLanes) {
    for (std::size_t c = 0; c < kFollowLanes; ++c) {
      const double moved2 =
          follow_one<kInFrame, kSlack>(s + c, body[s + c], q, bx, offset, at_build, xs, slack, shift);
      lane[c] = std::max(lane[c], moved2);
    }
  }
  for (; s < last; ++s) {
    const double moved2 =
        follow_one<kInFrame, kSlack>(s, body[s], q, bx, offset, at_build, xs, slack, shift);
    lane[0] = std::max(lane[0], moved2);
  }
}
template <bool kInFrame, bool kSlack>
inline void follow_run(Particles& p, const Bodies& b, std::size_t first, std::size_t last, const double* slack,
                       const FrameShift& shift, double (&lane)[kFollowLanes]) {
  if (first >= last) return;
  follow_span<kInFrame, kSlack>(first, last, p.body.data(), b.q.data(), b.x.data(), p.offset.data(),
                                p.x_at_build.data(), p.x.data(), slack, shift, lane);
}
/// Spheres [first, last) follow their bodies (follow_one); returns the largest displacement, the
/// frame's branch taken once.
inline double follow_bodies(Particles& p, const Bodies& b, std::size_t first, std::size_t last, const double* slack,
                            std::size_t slack_n, const FrameShift& shift) {
  double lane[kFollowLanes] = {};
  const std::size_t mid = std::clamp(slack_n, first, last);
  if (shift.identity) {
    follow_run<false, true>(p, b, first, mid, slack, shift, lane);
    follow_run<false, false>(p, b, mid, last, slack, shift, lane);
  } else {
    follow_run<true, true>(p, b, first, mid, slack, shift, lane);
    follow_run<true, false>(p, b, mid, last, slack, shift, lane);
  }
  double moved2 = 0;
  for (double m : lane) moved2 = std::max(moved2, m);
  return moved2;
}
}  // namespace

void Simulation::thread_bodies(int team, int t, std::size_t& first, std::size_t& last) const {
  // Thread t's share of the spheres follows the force loop's split, which is cut by cost; each
  // per-sphere and per-body loop of a step takes the same share, so that a sphere's state, and its
  // body's, stays on one core from phase to phase. With a static split of its own (equal counts) a
  // loop handed the spheres between the two cuts to the other core every step: on this project's
  // VMs, whose two vCPUs pass a cache line in ~500 ns, each thread of the clump bed waited 11-12 % of
  // the step at barriers, 9-10 % with one split (docs/performance.md, "2026-12-05 (fourth session)").
  const Bodies& b = bodies_;
  const std::size_t nb = b.size(), n = particles_.size();
  if (!b.indexed(n)) {  // bodies added since the last build
    equal_share(nb, team, t, first, last);
    return;
  }
  // Bodies are numbered in the order of their first sphere's slot (renumber_bodies), so those whose
  // first sphere lies in [s0, s1) are the bodies [first body at or after s0, first body at or after s1).
  std::size_t s0 = 0, s1 = 0;
  forces_.thread_spheres(n, team, t, s0, s1);
  first = t == 0 ? 0 : b.first_at(s0);
  last = t == team - 1 ? nb : b.first_at(s1);
  assert(first <= last);
}

std::size_t Simulation::first_crossing_body(int team, int t, std::size_t first, std::size_t last,
                                            std::size_t sphere_last) const {
  // A body spans at most body_slot_span_ slots, so only those starting within that of the range's
  // end can reach past it; the last thread's range has no end to reach past.
  if (t == team - 1) return last;
  return std::clamp(bodies_.first_at(sphere_last > body_slot_span_ ? sphere_last - body_slot_span_ : 0), first, last);
}

void Simulation::sum_body(std::size_t k, double half_kick) {
  Bodies& b = bodies_;
  assert(!spheres_hold_bodies_);  // (then a body's sums are its sphere's: sum_bodies)
  const Particles& p = particles_;
  Vec3 f{}, t{};
  for (std::uint32_t m = b.sphere_start[k]; m < b.sphere_start[k + 1]; ++m) {
    const std::uint32_t s = b.sphere_slot[m];
    f += p.force[s];
    t += cross(p.x[s] - b.x[k], p.force[s]) + p.torque[s];
  }
  // (The sums stored, then read back component by component: a local force stayed on GCC's stack
  // and was copied 16 bytes at a time, loads that waited on the 8-byte stores: sum_body 20 % slower.)
  b.force[k] = f + b.mass[k] * settings_.gravity;
  b.torque[k] = t;
  if (half_kick > 0) {
    b.v[k] += (half_kick * b.inv_mass[k]) * b.force[k];
    b.L[k] += half_kick * b.torque[k];
  }
}

void Simulation::sum_ready_bodies(int team, int thread, std::size_t from, std::size_t to, double half_kick,
                                  AfterForces::Progress& progress) {
  // In the force loop's sweep (beds beyond the caches), block by block: the bodies whose spheres'
  // forces were made a few blocks ago, still in the caches. Bodies are numbered in the order of
  // their first sphere and a body's slots ascend, so those ready are a prefix of the bodies that
  // start at or after `from`: [progress.first, progress.next) when done, up to progress.stop, the
  // first that may cross into the range above (left to sum_bodies, which waits for it).
  const Bodies& b = bodies_;
  if (!b.indexed(particles_.size())) return;  // bodies added since the last build: sum_bodies
  assert(!spheres_hold_bodies_);              // (wants_ready: a body per sphere)
  if (!progress.started) {
    std::size_t first = 0, last = 0, sphere_first = 0, sphere_last = 0;
    thread_bodies(team, thread, first, last);
    forces_.thread_spheres(particles_.size(), team, thread, sphere_first, sphere_last);
    progress.stop = first_crossing_body(team, thread, first, last, sphere_last);
    progress.first = progress.next = std::clamp(b.first_at(from), first, progress.stop);
    progress.started = true;
  }
  std::size_t k = progress.next;
  while (k < progress.stop && b.sphere_slot[b.sphere_start[k + 1] - 1] < to) sum_body(k++, half_kick);
  progress.next = k;
}

void Simulation::sum_bodies(const ForceTeam& team, double half_kick, const AfterForces::Progress& progress) {
  // Per body: its spheres' contact forces summed about its centre, plus gravity; with half_kick > 0
  // also the half kick that follows them in a step (one pass over the bodies instead of two). Run by
  // each thread of the force loop's team as soon as its own spheres' forces are complete
  // (ForceField::compute): the bodies that start in its range have their spheres in it, but for its
  // last few, which may have spheres in the ranges above; for those it waits for the threads above.
  // Those the sweep found ready (sum_ready_bodies) are done.
  const Bodies& b = bodies_;
  const Particles& p = particles_;
  const std::size_t n = p.size();
  const int thread = team.thread();
  std::size_t first = 0, last = 0, sphere_first = 0, sphere_last = 0;
  thread_bodies(team.size(), thread, first, last);
  // Where the spheres hold their bodies' state (spheres_hold_bodies_), body k is sphere k, in this
  // thread's range: its sums are the sphere's (update_body_copy makes the bodies' for a reader); only
  // the half kick is left to do.
  if (spheres_hold_bodies_) {
    if (half_kick > 0) {
      for (std::size_t k = first; k < last; ++k) kick_lone_sphere(particles_, bodies_, k, half_kick, settings_.gravity);
    }
    return;
  }
  forces_.thread_spheres(n, team.size(), thread, sphere_first, sphere_last);
  // The list build before the force loop indexed the spheres by body, so thread_bodies gave the
  // bodies that start in the range; were it not so, every body could have spheres anywhere.
  const bool by_range = b.indexed(n);
  assert(by_range);
  std::size_t crossing = last;  // bodies [crossing, last) may have spheres above the range
  if (!by_range) {
    team.wait_all();
  } else {
    crossing = first_crossing_body(team.size(), thread, first, last, sphere_last);
  }
  // The spheres above the range that belong to this thread's bodies (up to body_slot_span_ slots
  // past its end) had their forces written on the other core: requested once they are final, two
  // spheres per body, they have arrived when their bodies come (docs/performance.md, "2026-12-05
  // (fifth session)").
  std::size_t ahead = sphere_last, ahead_end = sphere_last;
  auto sum = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to; ++k) {
      for (int fetched = 0; fetched < 2 && ahead < ahead_end; ++ahead) {
        const std::size_t s = ahead;
        if (p.body[s] >= first && p.body[s] < last) {
          prefetch_for_read(&p.force[s]), prefetch_for_read(&p.torque[s]), prefetch_for_read(&p.x[s]);
          ++fetched;
        }
      }
      sum_body(k, half_kick);
    }
  };
  if (by_range && progress.started) {
    assert(progress.stop == crossing && first <= progress.first && progress.next <= crossing);
    sum(first, progress.first);
    sum(progress.next, crossing);
  } else {
    sum(first, crossing);
  }
  if (crossing < last) {
    team.wait_above();
    ahead_end = std::min(n, sphere_last + body_slot_span_);
    sum(crossing, last);
  }
}

void Simulation::compute_forces(double half_kick) {
  // The forces, then the bodies' sums in the same parallel region (ForceField::compute's follow-up).
  BodySums sums(*this, half_kick);
  read_motions();
  diag_ = forces_.compute(particles_, neighbors_, walls_, dt_, &sums);
  // omega = omega(q, L) is not made here: the next drift makes it afresh from L after its half kick,
  // and nothing in between reads it, so it is made only for a reader (update_body_omega). A clump's
  // omega, two rotations and three divisions, was a third of this loop on the clump bed.
  bodies_summed(half_kick > 0);
  // A blow-up is reported with the state it happened in: the sums above change only the bodies'
  // forces, velocities and angular momenta (a bed of loose spheres: its spheres' velocities), which
  // the report does not read.
  check_health();
}

void Simulation::read_motions() {
  // The spheres' v and omega: their own where they hold their bodies' state, else made from their
  // bodies' x, v and omega, the omega made by the drift's rotation (or setup's update_bodies) and not
  // changed since (the follow copied it into the spheres until 2026-12-08).
  assert(spheres_hold_bodies_ || !body_omega_lags_);
  const Bodies& b = bodies_;
  const ForceField::BodyMotion from_bodies{b.x.data(), b.v.data(), b.omega.data()};
  forces_.read_motion_from_bodies(spheres_hold_bodies_ ? ForceField::BodyMotion{} : from_bodies);
}

void Simulation::bodies_summed(bool kicked) {
  // (The kick leaves the spheres' velocities behind, and omega where the spheres hold it, even if a
  // reader brought them up to date since the drift: choose_skins.)
  if (kicked) body_omega_lags_ = true, sphere_state_lags_ = true;
  body_copy_lags_ = spheres_hold_bodies_;
}

void Simulation::update_bodies() const {
  if (body_copy_lags_) update_body_copy();
  if (body_omega_lags_) update_body_omega();
}

void Simulation::update_body_omega() const {
  // A cache of omega(q, L), hence const: the same numbers the kick made when it made them itself.
  Bodies& b = const_cast<Bodies&>(bodies_);
  const std::size_t nb = b.size();
#pragma omp parallel for if(nb >= parallel_min_items()) schedule(static)
  for (std::size_t k = 0; k < nb; ++k) b.omega[k] = body_angular_velocity(b.q[k], b.L[k], b.inertia[k]);
  body_omega_lags_ = false;
}

void Simulation::update_body_copy() const {
  // The spheres hold their bodies' state (spheres_hold_bodies_, or add_body is about to give it
  // back): body k is sphere k. (Omega is made from L, update_body_omega.)
  Bodies& b = const_cast<Bodies&>(bodies_);
  const Particles& p = particles_;
  const std::size_t n = p.size();
  const Vec3 g = settings_.gravity;
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    assert(p.body[k] == k);
    b.x[k] = p.x[k];
    b.v[k] = p.v[k];
    b.force[k] = lone_sphere_force(p.force[k], p.mass[k], g);
    b.torque[k] = lone_sphere_torque(p.force[k], p.torque[k]);
  }
  body_copy_lags_ = false;
}

void Simulation::move_spheres_with_bodies() {
  update_bodies();
  Particles& p = particles_;
  const std::size_t n = p.size();
  double moved2 = 0;
  const double* slack = neighbors_.slack2().data();
  const std::size_t slack_n = neighbors_.slack2().size();
  const FrameShift shift = frame_shift_at(time_);
#pragma omp parallel if(n >= parallel_min_items()) reduction(max : moved2)
  {
    std::size_t first = 0, last = 0;
    equal_share(n, omp_get_num_threads(), omp_get_thread_num(), first, last);
    moved2 = follow_bodies(p, bodies_, first, last, slack, slack_n, shift);
    for (std::size_t s = first; s < last; ++s) p.q[s] = bodies_.q[p.body[s]];
  }
  moved2_ = moved2;
  sphere_state_lags_ = true;  // (their v and omega are made from their bodies': follow_one)
}

bool Simulation::healthy() const {
  return diag_.bad_slot < 0 && diag_.slot_overflow < 0 && diag_.max_overlap_ratio <= settings_.max_overlap_ratio;
}

void Simulation::check_health() {
  if (healthy()) return;
  // Error path only from here: building the message may allocate.
  auto where = [&](std::int64_t s) {
    std::ostringstream o;
    const Vec3 x = particles_.x[s];
    o << "particle id " << particles_.id[s] << " (radius " << particles_.radius[s] << " m) at (" << x.x << ", " << x.y
      << ", " << x.z << ") m";
    return o.str();
  };
  auto stability_note = [&] {
    const StepStability now = check_stability();
    const StepStability& s = now.margin >= worst_stability_.margin ? now : worst_stability_;
    return "Per-body check: " + describe(s, bodies_) +
           (s.margin > 1 ? ". The step is too large for this contact network: lower the time step below " +
                               std::to_string(dt_ / s.margin) + " s (it is " + std::to_string(dt_) + " s)."
                         : ".");
  };
  std::ostringstream msg;
  msg << "t = " << time_ << " s (step " << steps_ << "): ";
  if (diag_.bad_slot >= 0) {
    msg << "non-finite force or torque on " << where(diag_.bad_slot)
        << ". Likely causes: a time step too large for the stiffest contact (" << time_step_report()
        << "), or particles inserted overlapping. " << stability_note();
    throw BlowUp(msg.str());
  }
  if (diag_.slot_overflow >= 0) {
    msg << where(diag_.slot_overflow) << " touches more than " << ForceField::kWallSlots
        << " wall features at once; walls overlap or the particle has tunnelled into a corner.";
    throw BlowUp(msg.str());
  }
  if (diag_.max_overlap_ratio > settings_.max_overlap_ratio) {
    if (sphere_state_lags_) update_sphere_state();  // (the speeds named below; follow_one)
    // Find the particle and what it overlaps (error path only, so a serial search is fine).
    std::int64_t worst = -1;
    double worst_ratio = 0;
    std::string partner;
    auto describe = [&](std::size_t j) {
      std::ostringstream o;
      o << "particle id " << particles_.id[j] << " (" << materials_[particles_.material[j]].name << ", radius "
        << particles_.radius[j] << " m, speed " << norm(particles_.v[j]) << " m/s)";
      return o.str();
    };
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      for (std::uint32_t k = neighbors_.begin(i); k < neighbors_.end(i); ++k) {
        const std::uint32_t j = neighbors_.partner(k);
        const double ov = particles_.radius[i] + particles_.radius[j] - norm(particles_.x[i] - particles_.x[j]);
        const double r = ov / std::min(particles_.radius[i], particles_.radius[j]);
        if (r > worst_ratio) {
          const bool i_small = particles_.radius[i] <= particles_.radius[j];
          worst_ratio = r, worst = static_cast<std::int64_t>(i_small ? i : j);
          partner = describe(i_small ? j : i);
        }
      }
      for (const Wall& w : walls_) {
        WallContact wc[ForceField::kWallSlots];
        const int n = w.contacts(particles_.x[i], particles_.radius[i], wc, ForceField::kWallSlots);
        for (int q = 0; q < n; ++q) {
          if (wc[q].overlap / particles_.radius[i] > worst_ratio) {
            worst_ratio = wc[q].overlap / particles_.radius[i], worst = static_cast<std::int64_t>(i);
            partner = "wall '" + w.name() + "'";
          }
        }
      }
    }
    msg << "overlap of " << diag_.max_overlap_ratio * 100 << " % of the radius (limit "
        << settings_.max_overlap_ratio * 100 << " %)"
        << (worst >= 0 ? " at " + where(worst) + " (" + materials_[particles_.material[worst]].name + ", speed " +
                             std::to_string(norm(particles_.v[worst])) + " m/s) against " + partner
                       : std::string())
        << ". Likely causes: time step too large (" << time_step_report()
        << "), impact speeds far above what the stiffness allows, or overlapping insertion. " << stability_note();
    throw BlowUp(msg.str());
  }
}


double Simulation::drift_part(int team, int thread, double dt, std::uint64_t epoch) {
  // Half kick, drift and free rotation of the bodies, then the spheres follow: two loops, each
  // thread on the bodies and spheres it takes in the force loop (thread_bodies). The sphere loop runs
  // over slots (cell order) and reads its body, which is cheaper than each body writing its spheres
  // (slots scattered over the arrays; measured: docs/performance.md).
  Bodies& b = bodies_;
  Particles& p = particles_;
  const std::size_t n = p.size();
  const double half = 0.5 * dt;
  double moved2 = 0;
  const double* slack = neighbors_.slack2().data();
  const std::size_t slack_n = neighbors_.slack2().size();
  // With the spheres indexed by body, a thread's bodies are those that start in its sphere range
  // (thread_bodies), so its spheres belong to its own bodies, but for the first few of those crossing
  // from the ranges below. Each thread turns those crossing bodies first and posts `epoch`; the
  // thread above waits for the posts below before its sphere loop (dem/team_signals.hpp). Else
  // (bodies added since the last build) the bodies are shared out equally and the sphere loop waits
  // at a barrier.
  const bool by_range = b.indexed(n);
  std::size_t body_first = 0, body_last = 0, sphere_first = 0, sphere_last = 0;
  thread_bodies(team, thread, body_first, body_last);
  forces_.thread_spheres(n, team, thread, sphere_first, sphere_last);
  // The first spheres of this range, which the thread below read as partners in its force loop
  // (slots [sphere_first, reach_before(sphere_first))): their lines, written in the sphere loop
  // below, are requested for writing a line per body in the body loop (dem/boundary_lines.hpp):
  // x, and v and omega where the spheres hold their bodies' state (else they are not copied: follow_one).
  BoundaryLines<3> boundary;
  if (thread > 0 && sphere_first < sphere_last && neighbors_.starts().size() == n + 1) {
    // (reach_before(s) is below s when no pair reaches across s.)
    const std::size_t end = std::clamp<std::size_t>(neighbors_.reach_before(sphere_first), sphere_first, sphere_last);
    const bool own = spheres_hold_bodies_;
    const Vec3* const v = own ? &p.v[sphere_first] : nullptr;
    const Vec3* const omega = own ? &p.omega[sphere_first] : nullptr;
    boundary = BoundaryLines<3>({&p.x[sphere_first], v, omega}, (end - sphere_first) * sizeof(Vec3));
  }
  // (The list's frame where the spheres will be, at the step's end; the walls move there after the drift.)
  const FrameShift shift = frame_shift_at(time_ + dt);
  // Bodies in chunks: the anisotropic ones' rotations are evaluated together, vectorised, and the
  // isotropic ones' (spheres) likewise (dem/rotation_batch.hpp; the same numbers as one body at a time).
  // Where the spheres hold their bodies' state (spheres_hold_bodies_: body k is sphere k), the
  // bodies' x, v, omega are the spheres' and their force and torque are made from the spheres' sums
  // (as sum_body made them), so the spheres need not follow: only their displacements are taken,
  // chunk by chunk, while the chunk is in the caches.
  RotationBatch batch;
  IsotropicRotationBatch isotropic;
  const Vec3 gravity = settings_.gravity;
  auto turn_as = [&](auto in_spheres, std::size_t from, std::size_t to) {  // bodies [from, to)
    constexpr bool kInSpheres = decltype(in_spheres)::value;
    Vec3* const x = kInSpheres ? p.x.data() : b.x.data();
    Vec3* const v = kInSpheres ? p.v.data() : b.v.data();
    Vec3* const omega = kInSpheres ? p.omega.data() : b.omega.data();
    auto rotate_alone = [&](std::size_t k) {  // bodies the batch's series cannot turn
      free_rotation_step(b.q[k], b.L[k], b.inertia[k], dt);
      omega[k] = body_angular_velocity(b.q[k], b.L[k], b.inertia[k]);
    };
    for (std::size_t first = from; first < to; first += RotationBatch::kCapacity) {
      const std::size_t last = std::min(to, first + RotationBatch::kCapacity);
      batch.size = 0, isotropic.size = 0;
      for (std::size_t k = first; k < last; ++k) {
        boundary.fetch_next_for_write();
        if constexpr (kInSpheres) {
          kick_lone_sphere(p, b, k, half, gravity);
        } else {
          v[k] += (half * b.inv_mass[k]) * b.force[k];
          b.L[k] += half * b.torque[k];
        }
        x[k] += dt * v[k];
        if constexpr (kInSpheres) {  // (the sphere's copies of its body's mass and inertia: loose_spheres_in_order)
          isotropic.add(static_cast<std::uint32_t>(k), b.q[k], b.L[k], p.inertia[k]);
          continue;
        }
        const Vec3& inertia = b.inertia[k];
        if (inertia.x == inertia.y && inertia.y == inertia.z) {  // a sphere: one exact rotation
          isotropic.add(static_cast<std::uint32_t>(k), b.q[k], b.L[k], inertia.x);
        } else {
          batch.add(static_cast<std::uint32_t>(k), b.q[k], b.L[k], inertia);
        }
      }
      isotropic.rotate(dt);
      for (int c = 0; c < isotropic.size; ++c) {
        const std::uint32_t k = isotropic.body[c];
        const Vec3 w{isotropic.wx[c], isotropic.wy[c], isotropic.wz[c]};
        if (isotropic.in_range[c]) {
          b.q[k] = {isotropic.qw[c], isotropic.qx[c], isotropic.qy[c], isotropic.qz[c]};
        } else {  // turned too far in one step for the series: the exact turn, from the old q
          free_rotation_isotropic(b.q[k], w, dt);
        }
        omega[k] = w;
      }
      batch.rotate(dt);
      for (int c = 0; c < batch.size; ++c) {
        const std::uint32_t k = batch.body[c];
        if (batch.in_range[c]) {
          b.q[k] = {batch.qw[c], batch.qx[c], batch.qy[c], batch.qz[c]};
          omega[k] = {batch.wx[c], batch.wy[c], batch.wz[c]};
        } else {  // turned too far in one step for the series: the general path, from the old q
          rotate_alone(k);
        }
      }
      if constexpr (kInSpheres) moved2 = std::max(moved2, moved_spheres(p, first, last, slack, slack_n, shift));
    }
  };
  const bool in_spheres = spheres_hold_bodies_;
  auto turn = [&](std::size_t from, std::size_t to) {
    if (in_spheres) {
      turn_as(std::true_type{}, from, to);
    } else {
      turn_as(std::false_type{}, from, to);
    }
  };
  if (by_range) {
    const std::size_t crossing = first_crossing_body(team, thread, body_first, body_last, sphere_last);
    turn(crossing, body_last);
    step_signals_.post(thread, epoch);
    turn(body_first, crossing);
    for (int below = 0; below < thread; ++below) step_signals_.wait(below, epoch);
  } else {
    turn(body_first, body_last);
#pragma omp barrier
  }
  if (in_spheres) return moved2;
  return std::max(moved2, follow_bodies(p, b, sphere_first, sphere_last, slack, slack_n, shift));
}

void Simulation::update_sphere_state() const {
  // The spheres' orientations, and their velocities at the full step, are for output and
  // diagnostics only (the force loop needs neither; the next drift sets the velocities afresh), so
  // they are brought up to date on demand: a cache of the bodies' state, hence const.
  update_bodies();
  Particles& p = const_cast<Particles&>(particles_);
  const Bodies& b = bodies_;
  const std::size_t n = p.size();
  const bool own_v = !spheres_hold_bodies_;  // (else the spheres' velocities are their bodies')
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static)
  for (std::size_t s = 0; s < n; ++s) {
    const std::uint32_t k = p.body[s];
    p.q[s] = b.q[k];
    if (own_v) p.v[s] = b.v[k] + cross(b.omega[k], rotate(b.q[k], p.offset[s]));
    p.omega[s] = b.omega[k];
  }
  sphere_state_lags_ = false;
}

void Simulation::step() { run_steps(1); }

void Simulation::run_steps(std::uint64_t n) {
  if (n == 0) return;
  if (!ready_) setup();
  for (std::uint64_t done = 0; done < n;) done += steps_in_region(n - done);
}

bool Simulation::stability_due() const {
  return settings_.stability_interval > 0 && steps_ % settings_.stability_interval == 0;
}

std::uint64_t Simulation::steps_in_region(std::uint64_t most) {
  // A step is
  //   drift (each thread its bodies and spheres);
  //   the time, the walls; a list build if the list is stale (or the adaptive skin asks for one);
  //   the forces and the bodies' sums with the second half kick (each thread its spheres, its bodies);
  //   the health check; every stability_interval steps the stability check.
  // Steps run in one parallel region for as long as they need nothing but the threads' loops: the
  // threads meet twice a step, after the drift and after the sums, where thread 0 does the step's
  // serial part (TeamSignals::meet). A step that needs a list build, the adaptive skin's check, masks
  // of the walls made again, the stability check or a blow-up report leaves the region and is
  // finished outside it (finish_step). A libgomp region costs a fork and a join (futex calls, ~1 µs
  // each on this project's VMs): 8-15 µs a region beyond the threads' work (docs/performance.md,
  // "2026-12-05 (sixth session)"); a meet costs a line passed each way.
  const std::size_t n = particles_.size();
  const int max_team = n >= parallel_min_items() ? omp_get_max_threads() : 1;
  step_signals_.reserve(max_team);
  if (moved2_of_.size() < static_cast<std::size_t>(max_team)) moved2_of_.resize(max_team);
  // Per step: the drift's crossing bodies, arrival and release after the drift, after the sums.
  constexpr std::uint64_t kEpochs = 5;
  const std::uint64_t base = step_signals_.next_epochs(kEpochs * most);
  BodySums sums(*this, 0.5 * dt_);
  enum class Left { no, after_drift, after_forces, error };
  Left left = Left::no;  // written by thread 0 in a meet, read by the others after it
  std::uint64_t done = 0;
  std::exception_ptr error;
#pragma omp parallel if(max_team > 1) num_threads(max_team)
  {
    const int team = omp_get_num_threads(), thread = omp_get_thread_num();
    for (std::uint64_t i = 0;; ++i) {
      const std::uint64_t e = base + kEpochs * i;
      moved2_of_[thread].value = drift_part(team, thread, dt_, e);
      step_signals_.meet(team, thread, e + 1, e + 2, [&] {
        try {
          left = drifted(team) ? Left::no : Left::after_drift;
        } catch (...) {  // (nothing there should throw; if it does, it must not end the process)
          error = std::current_exception();
          left = Left::error;
        }
      });
      if (left != Left::no) break;
      forces_.pass(team, thread, particles_, neighbors_, walls_, dt_, &sums);
      step_signals_.meet(team, thread, e + 3, e + 4, [&] {
        diag_ = forces_.finish(dt_);
        bodies_summed(true);
        ++done;
        if (!healthy() || stability_due() || done == most) left = Left::after_forces;
      });
      if (left != Left::no) break;
    }
  }
  if (left == Left::error) std::rethrow_exception(error);
  if (left == Left::after_drift) {
    finish_step();
    return done + 1;
  }
  check_health();  // throws when the step has blown up
  if (stability_due()) control_step(check_stability(), settings_.stability_interval);
  return done;
}

bool Simulation::drifted(int team) {
  // The serial part after the drift (thread 0, the team waiting): true if the step's forces may be
  // computed in the region.
  double moved2 = 0;
  for (int t = 0; t < team; ++t) moved2 = std::max(moved2, moved2_of_[t].value);
  moved2_ = moved2;
  // Every body's omega made afresh by the drift: in the bodies' array, or, where the spheres hold
  // their bodies' state, in the spheres' only (the bodies' then made from L for a reader: the same
  // (1 / I) L, the same bits).
  body_omega_lags_ = spheres_hold_bodies_;
  body_copy_lags_ = spheres_hold_bodies_;
  sphere_state_lags_ = true;  // orientations (output only) are not copied there; velocities go stale at the kick
  time_ += dt_;
  ++steps_;
  for (Wall& w : walls_) w.move_to(time_);
  if (neighbors_.stale(particles_, moved2_) || skin_check_due()) return false;
  if (!forces_.begins_in_team(particles_, neighbors_, walls_, team)) return false;
  read_motions();
  forces_.begin(particles_, neighbors_, walls_, team);
  return true;
}

void Simulation::finish_step() {
  // The rest of a step after its drift, outside a region: a list build if due, the forces and sums.
  if (neighbors_.stale(particles_, moved2_)) {
    rebuild(choose_skins());
  } else if (const std::optional<SkinChoice> skins = early_rebuild()) {
    rebuild(*skins);  // (chosen once: own_skin_ is still theirs)
  }
  compute_forces(0.5 * dt_);  // and the bodies' sums with the second half kick; the health check
  if (stability_due()) control_step(check_stability(), settings_.stability_interval);
}

void Simulation::check_and_control_step(int interval) { control_step(check_stability(), interval); }

void Simulation::control_step(const StepStability& now, int interval) {
  // Between steps, outside the threads' region: the next region's steps take the new dt_ (its
  // second half kick too: BodySums is made per region).
  const double next = settings_.step_control.next(dt_, dt_ceiling_, now.margin, interval);
  if (next == dt_) return;
  dt_ = next;
  ++dt_changes_;
  lowest_dt_ = std::min(lowest_dt_, dt_);
}

const StepStability& Simulation::check_stability() {
  if (body_copy_lags_) update_body_copy();
  stability_ = stability_monitor_.assess(particles_, bodies_, neighbors_, walls_, forces_, dt_);
  if (stability_.margin > worst_stability_.margin) worst_stability_ = stability_;
  return stability_;
}


Energy Simulation::energy() const {
  if (body_copy_lags_) update_body_copy();
  Energy e;
  const Bodies& b = bodies_;
  for (std::size_t k = 0; k < b.size(); ++k) {
    e.kinetic_translation += 0.5 * b.mass[k] * norm2(b.v[k]);
    e.kinetic_rotation += rotational_energy(b.q[k], b.L[k], b.inertia[k]);
    e.potential -= b.mass[k] * dot(settings_.gravity, b.x[k]);
  }
  if (ready_) {
    const ContactEnergy c = forces_.contact_energy(particles_, neighbors_, walls_);
    e.elastic_normal = c.normal;
    e.elastic_tangential = c.tangential;
  }
  return e;
}

std::size_t Simulation::bytes() const {
  const std::size_t per_sphere = sizeof(std::uint64_t) + 2 * sizeof(std::int32_t) + 4 * sizeof(double) +
                                 7 * sizeof(Vec3) + sizeof(Quat) + sizeof(std::uint32_t);
  const std::size_t per_body = sizeof(std::uint64_t) + sizeof(std::int32_t) + 2 * sizeof(double) + 7 * sizeof(Vec3) +
                               sizeof(Quat) + 2 * sizeof(std::uint32_t);
  return particles_.size() * per_sphere + bodies_.size() * per_body + neighbors_.bytes() + forces_.bytes();
}

}  // namespace grainscale::dem
