#include "dem/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "dem/input_error.hpp"
#include "dem/time_step.hpp"

namespace grainscale::dem {

Simulation::Simulation(MaterialTable materials, SimulationSettings settings)
    : materials_(std::move(materials)), settings_(settings) {}

std::uint64_t Simulation::add_sphere(int material, double radius, const Vec3& x, const Vec3& v, const Vec3& omega) {
  if (material < 0 || material >= materials_.size()) throw InputError("add_sphere: material index out of range");
  if (!(radius > 0) || !std::isfinite(radius)) throw InputError("add_sphere: radius must be positive and finite");
  const std::uint64_t id = next_id_++;
  particles_.add_sphere(id, material, radius, materials_[material].density, x, v, omega);
  ready_ = false;
  return id;
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
  s << "time step " << dt_ << " s = " << dt_ / rayleigh_time() * 100 << " % of the Rayleigh time " << rayleigh_time()
    << " s" << (settings_.time_step > 0 ? " (set in the input)" : " (automatic)");
  return s.str();
}

void Simulation::setup() {
  // Every material pair that can meet must have interaction properties.
  std::set<int> used(particles_.material.begin(), particles_.material.end());
  for (int a : used) {
    for (int b : used) materials_.pair(a, b);
    for (const Wall& w : walls_) materials_.pair(a, w.material());
  }
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (!std::isfinite(materials_[particles_.material[i]].shear_modulus)) {
      throw InputError("material '" + materials_[particles_.material[i]].name +
                       "' is rigid (infinite shear modulus) and cannot be used for particles");
    }
  }
  if (settings_.time_step > 0) {
    dt_ = settings_.time_step;
  } else {
    if (particles_.size() == 0) throw InputError("cannot choose a time step automatically without particles");
    dt_ = settings_.time_step_fraction * rayleigh_time();
  }
  double r_max = 0;
  for (double r : particles_.radius) r_max = std::max(r_max, r);
  skin_ = settings_.skin > 0 ? settings_.skin : 0.2 * r_max;
  forces_.setup(materials_, walls_, settings_.rolling);
  forces_.resize(particles_.size());
  rebuild();
  compute_forces();
  ready_ = true;
}

void Simulation::rebuild() {
  const std::vector<std::uint32_t>& order = neighbors_.sort_by_cell(particles_, skin_);
  particles_.permute(order);
  forces_.permute(order);
  neighbors_.build(particles_, skin_, order);
}

void Simulation::compute_forces() {
  diag_ = forces_.compute(particles_, neighbors_, walls_, settings_.gravity, dt_);
  check_health();
}

void Simulation::check_health() const {
  if (diag_.bad_slot < 0 && diag_.slot_overflow < 0 && diag_.max_overlap_ratio <= settings_.max_overlap_ratio) return;
  // Error path only from here: building the message may allocate.
  auto where = [&](std::int64_t s) {
    std::ostringstream o;
    const Vec3 x = particles_.x[s];
    o << "particle id " << particles_.id[s] << " (radius " << particles_.radius[s] << " m) at (" << x.x << ", " << x.y
      << ", " << x.z << ") m";
    return o.str();
  };
  std::ostringstream msg;
  msg << "t = " << time_ << " s (step " << steps_ << "): ";
  if (diag_.bad_slot >= 0) {
    msg << "non-finite force or torque on " << where(diag_.bad_slot)
        << ". Likely causes: a time step too large for the stiffest contact (" << time_step_report()
        << "), or particles inserted overlapping.";
    throw BlowUp(msg.str());
  }
  if (diag_.slot_overflow >= 0) {
    msg << where(diag_.slot_overflow) << " touches more than " << ForceField::kWallSlots
        << " wall features at once; walls overlap or the particle has tunnelled into a corner.";
    throw BlowUp(msg.str());
  }
  if (diag_.max_overlap_ratio > settings_.max_overlap_ratio) {
    // Find the particle (error path only, so a serial search is fine).
    std::int64_t worst = -1;
    double worst_ratio = 0;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      for (std::uint32_t k = neighbors_.begin(i); k < neighbors_.end(i); ++k) {
        const std::uint32_t j = neighbors_.partner(k);
        const double ov = particles_.radius[i] + particles_.radius[j] - norm(particles_.x[i] - particles_.x[j]);
        const double r = ov / std::min(particles_.radius[i], particles_.radius[j]);
        if (r > worst_ratio) worst_ratio = r, worst = static_cast<std::int64_t>(i);
      }
      for (const Wall& w : walls_) {
        WallContact wc[ForceField::kWallSlots];
        const int n = w.contacts(particles_.x[i], particles_.radius[i], wc, ForceField::kWallSlots);
        for (int q = 0; q < n; ++q) {
          if (wc[q].overlap / particles_.radius[i] > worst_ratio) {
            worst_ratio = wc[q].overlap / particles_.radius[i], worst = static_cast<std::int64_t>(i);
          }
        }
      }
    }
    msg << "overlap of " << diag_.max_overlap_ratio * 100 << " % of the radius (limit "
        << settings_.max_overlap_ratio * 100 << " %)" << (worst >= 0 ? " at " + where(worst) : std::string())
        << ". Likely causes: time step too large (" << time_step_report()
        << "), impact speeds far above what the stiffness allows, or overlapping insertion.";
    throw BlowUp(msg.str());
  }
}

void Simulation::kick(double half_dt) {
  Particles& p = particles_;
  const std::size_t n = p.size();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    p.v[i] += (half_dt * p.inv_mass[i]) * p.force[i];
    p.omega[i] += (half_dt * p.inv_inertia[i]) * p.torque[i];
  }
}

void Simulation::step() {
  if (!ready_) setup();
  Particles& p = particles_;
  const std::size_t n = p.size();
  const double dt = dt_, half = 0.5 * dt_;
  // Half kick, drift and the largest displacement since the last neighbour build, in one pass
  // (one parallel region instead of three: at a few thousand particles a step takes ~0.2 ms and
  // each fork/join costs microseconds).
  double moved2 = 0;
#pragma omp parallel for schedule(static) reduction(max : moved2)
  for (std::size_t i = 0; i < n; ++i) {
    p.v[i] += (half * p.inv_mass[i]) * p.force[i];
    p.omega[i] += (half * p.inv_inertia[i]) * p.torque[i];
    p.x[i] += dt * p.v[i];
    p.q[i] = advance(p.q[i], p.omega[i], dt);
    moved2 = std::max(moved2, norm2(p.x[i] - p.x_at_build[i]));
  }
  time_ += dt;
  ++steps_;
  if (neighbors_.stale(p, moved2)) rebuild();
  compute_forces();
  kick(half);
}

void Simulation::run_steps(std::uint64_t n) {
  for (std::uint64_t s = 0; s < n; ++s) step();
}

Energy Simulation::energy() const {
  Energy e;
  const Particles& p = particles_;
  for (std::size_t i = 0; i < p.size(); ++i) {
    e.kinetic_translation += 0.5 * p.mass[i] * norm2(p.v[i]);
    e.kinetic_rotation += 0.5 * p.inertia[i] * norm2(p.omega[i]);
    e.potential -= p.mass[i] * dot(settings_.gravity, p.x[i]);
  }
  if (ready_) {
    const ContactEnergy c = forces_.contact_energy(p, neighbors_, walls_);
    e.elastic_normal = c.normal;
    e.elastic_tangential = c.tangential;
  }
  return e;
}

std::size_t Simulation::bytes() const {
  const Particles& p = particles_;
  const std::size_t per = sizeof(std::uint64_t) + sizeof(std::int32_t) + 5 * sizeof(double) + 6 * sizeof(Vec3) +
                          sizeof(Quat);
  return p.size() * per + neighbors_.bytes() + forces_.bytes();
}

}  // namespace grainscale::dem
