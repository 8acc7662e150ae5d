#pragma once
// A DEM system of spheres and walls, advanced by velocity Verlet:
//
//   v += dt/2 F/m,  w += dt/2 T/I          (half kick)
//   x += dt v,      q <- exp(dt w) q       (drift)
//   rebuild neighbour list if needed; F, T = forces(x, v, w)
//   v += dt/2 F/m,  w += dt/2 T/I          (half kick)
//
// Velocity-dependent forces (damping, friction) see the half-step velocities, as in LIGGGHTS. For
// conservative contacts the scheme is symplectic: energy does not drift (tests/dem/test_conservation).
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem/force_field.hpp"
#include "dem/material.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/particles.hpp"
#include "dem/rolling_model.hpp"
#include "dem/wall.hpp"

namespace grainscale::dem {

struct SimulationSettings {
  Vec3 gravity{0, 0, -9.81};
  double time_step = 0;             // s; 0 = automatic: time_step_fraction x Rayleigh time
  double time_step_fraction = 0.2;  // of the smallest Rayleigh time among the particles
  double skin = 0;                  // m; 0 = automatic: 0.1 x largest particle diameter
  RollingSettings rolling;
  double max_overlap_ratio = 0.3;   // overlap / radius that stops the run as a blow-up
  double scale_factor = 1;          // particle scale factor (metadata, written to every snapshot)
};

/// Thrown when the state has become unphysical; the message is the diagnosis.
class BlowUp : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Energy {
  double kinetic_translation = 0, kinetic_rotation = 0;
  double potential = 0;  // gravitational, relative to the origin
  double elastic_normal = 0, elastic_tangential = 0;
  double total() const { return kinetic_translation + kinetic_rotation + potential + elastic_normal + elastic_tangential; }
};

class Simulation {
 public:
  Simulation(MaterialTable materials, SimulationSettings settings);

  /// Add a solid sphere of the given material; returns its permanent id.
  std::uint64_t add_sphere(int material, double radius, const Vec3& x, const Vec3& v = {}, const Vec3& omega = {});
  void add_wall(std::string name, std::shared_ptr<const WallGeometry> geometry, int material, const WallPose& pose = {});

  /// Validate the set-up, choose the time step, build neighbours and compute the first forces.
  /// Called by the first step() if not called before.
  void setup();
  void step();
  void run_steps(std::uint64_t n);

  double time() const { return time_; }
  std::uint64_t steps() const { return steps_; }
  double dt() const { return dt_; }
  /// Smallest Rayleigh time over the particles present.
  double rayleigh_time() const;
  /// One line on how dt was chosen, for the log.
  std::string time_step_report() const;

  Particles& particles() { return particles_; }
  const Particles& particles() const { return particles_; }
  std::vector<Wall>& walls() { return walls_; }
  const std::vector<Wall>& walls() const { return walls_; }
  const MaterialTable& materials() const { return materials_; }
  const SimulationSettings& settings() const { return settings_; }
  const NeighborList& neighbors() const { return neighbors_; }
  const ForceDiagnostics& diagnostics() const { return diag_; }

  Energy energy() const;
  /// Bytes of particle, neighbour and contact data (memory report).
  std::size_t bytes() const;

 private:
  void rebuild();
  void compute_forces();
  void check_health() const;
  void kick(double half_dt);

  MaterialTable materials_;
  SimulationSettings settings_;
  Particles particles_;
  std::vector<Wall> walls_;
  NeighborList neighbors_;
  ForceField forces_;
  ForceDiagnostics diag_;
  double time_ = 0, dt_ = 0, skin_ = 0;
  std::uint64_t steps_ = 0, next_id_ = 0;
  bool ready_ = false;
};

}  // namespace grainscale::dem
