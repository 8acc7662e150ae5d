#pragma once
// A DEM system of rigid bodies (loose spheres and clumps of spheres) and walls, advanced by velocity
// Verlet with a symplectic rotation step:
//
//   v += dt/2 F/m,  L += dt/2 T                    (half kick, bodies)
//   x += dt v,      q <- free rotation by L for dt (drift; dem/rigid_rotation.hpp)
//   spheres follow their bodies; rebuild the neighbour list if needed
//   F, T = contact forces on spheres, summed per body, plus gravity
//   v += dt/2 F/m,  L += dt/2 T                    (half kick, bodies)
//
// Velocity-dependent forces (damping, friction) see the half-step velocities, as in LIGGGHTS. For
// conservative contacts the scheme is symplectic: energy does not drift (tests/dem/test_conservation).
#include <cstdint>
#include <optional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dem/bodies.hpp"
#include "dem/force_field.hpp"
#include "dem/mass_properties.hpp"
#include "dem/material.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/particles.hpp"
#include "dem/rolling_model.hpp"
#include "dem/shape.hpp"
#include "dem/step_control.hpp"
#include "dem/step_stability.hpp"
#include "dem/team_signals.hpp"
#include "dem/wall.hpp"

namespace grainscale::dem {

struct SimulationSettings {
  Vec3 gravity{0, 0, -9.81};
  double time_step = 0;             // s; 0 = automatic: time_step_fraction x Rayleigh time
  double time_step_fraction = 0.2;  // of the smallest Rayleigh time among the particles
  double skin = 0;                  // m; > 0: fixed; 0 = adaptive, chosen at each list build (dem/adaptive_skin.hpp)
  double skin_max = 0;              // m; largest adaptive skin; 0 = 0.2 x the largest radius present
  // The frame the neighbour list measures travel in (dem/list_frame.hpp): chosen at each build (the
  // first moving wall's where the spheres move less there), or always the world's (as before
  // 2026-12-06's afternoon: for comparisons).
  enum class ListFrameChoice { automatic, world };
  ListFrameChoice list_frame = ListFrameChoice::automatic;
  // A bed of loose spheres only keeps its bodies' state in its spheres' arrays (Simulation::
  // spheres_hold_bodies_), or never (its bodies keep a copy of their own, as before 2026-12-07: for
  // comparisons; the same numbers either way).
  bool loose_bodies_in_spheres = true;
  RollingSettings rolling;
  double max_overlap_ratio = 0.3;   // overlap / radius that stops the run as a blow-up
  double scale_factor = 1;          // particle scale factor (metadata, written to every snapshot)
  std::string time_step_note;       // how a preset time_step was chosen, for the log (optional)
  int stability_interval = 20;      // steps between per-body step-stability checks (dem/step_stability.hpp)
  StepControl step_control;          // fixed, or the step kept below a stability margin (dem/step_control.hpp)
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

/// The complete dynamic state of a Simulation between two steps, as a checkpoint holds it
/// (dem/checkpoint.hpp) and Simulation::restore takes it back. Sphere arrays are in slot order: the
/// force sums run over slots and neighbour-list entries, so continuing bit for bit needs the same
/// order, not just the same particles. Walls are not here: their poses follow from the time.
struct SimulationState {
  double time = 0, dt = 0, skin = 0;
  std::uint64_t steps = 0, next_sphere_id = 0, neighbor_builds = 0;
  Particles particles;                    // every array, x_at_build included
  Bodies bodies;                          // every array; sphere_start/slot are checked, then rebuilt
  std::vector<std::string> shape_names;
  std::vector<std::uint32_t> neighbor_start, neighbor_partner;  // NeighborList::starts(), partners()
  std::vector<ContactHistory> neighbor_history;
  std::vector<double> neighbor_skin;      // NeighborList::skins() (empty: all `skin`)
  int neighbor_frame_wall = -1;           // NeighborList::frame(): its wall (-1: the world)
  WallPose neighbor_frame_at_build;       // and that wall's pose at the build (its origin, orientation)
  std::vector<std::uint8_t> wall_count;   // per slot: wall contacts in use
  std::vector<WallSlot> wall_slots;       // those contacts, slot by slot (sum of wall_count)
  ForceDiagnostics diagnostics;           // of the last force computation
  StepStability stability, worst_stability;
  double lowest_dt = 0;                   // the smallest step taken since setup (0: not recorded)
  std::uint64_t dt_changes = 0;           // how often the step control changed the step
};

class Simulation {
 public:
  Simulation(MaterialTable materials, SimulationSettings settings);

  /// Add a loose solid sphere of the given material; returns its body id (which is also the id of
  /// its one sphere when only loose spheres are added). Particles may be added to a running
  /// simulation (pouring): place them clear of the others; contact histories are kept.
  std::uint64_t add_sphere(int material, double radius, const Vec3& x, const Vec3& v = {}, const Vec3& omega = {});
  /// Add a clump of `shape` whose file frame is turned by `orientation` and whose centre of mass is at
  /// `x`. Mass from `density` times the union volume (overlaps counted once). Returns its body id.
  std::uint64_t add_clump(const Shape& shape, int material, double density, const Vec3& x, const Quat& orientation = {},
                          const Vec3& v = {}, const Vec3& omega = {});
  void add_wall(std::string name, std::shared_ptr<const WallGeometry> geometry, int material, const WallPose& pose = {});

  /// Validate the set-up, choose the time step, build neighbours and compute the first forces.
  /// Called by the first step() if not called before.
  void setup();
  void step();
  void run_steps(std::uint64_t n);

  double time() const { return time_; }
  std::uint64_t steps() const { return steps_; }
  double dt() const { return dt_; }
  /// The step set in the input (time.step, or the fraction of the Rayleigh time): the step itself, or
  /// with settings().step_control in stability mode the most the step may be (dem/step_control.hpp).
  double dt_ceiling() const { return dt_ceiling_; }
  /// The smallest step taken since setup, and how often the step control changed the step.
  double lowest_dt() const { return lowest_dt_; }
  std::uint64_t dt_changes() const { return dt_changes_; }
  /// Smallest Rayleigh time over the particles present.
  double rayleigh_time() const;
  /// One line on how dt was chosen, for the log.
  std::string time_step_report() const;

  /// The component spheres (what contacts act on). Their x, v and omega follow their bodies: they are
  /// not the way to move a body (in a bed of loose spheres they are its state, elsewhere a copy).
  Particles& particles() {
    if (sphere_state_lags_) update_sphere_state();
    return particles_;
  }
  const Particles& particles() const {
    if (sphere_state_lags_) update_sphere_state();
    return particles_;
  }
  /// The rigid bodies (what is integrated).
  const Bodies& bodies() const {
    update_bodies();
    return bodies_;
  }
  const std::vector<std::string>& shape_names() const { return shape_names_; }
  std::vector<Wall>& walls() { return walls_; }
  const std::vector<Wall>& walls() const { return walls_; }
  const MaterialTable& materials() const { return materials_; }
  const SimulationSettings& settings() const { return settings_; }
  const NeighborList& neighbors() const { return neighbors_; }
  const ForceDiagnostics& diagnostics() const { return diag_; }
  /// Per-body step stability at the last check, and the worst seen since setup (dem/step_stability.hpp).
  const StepStability& stability() const { return stability_; }
  const StepStability& worst_stability() const { return worst_stability_; }
  const StepStabilityMonitor& stability_monitor() const { return stability_monitor_; }
  /// Check step stability now (also done every settings().stability_interval steps).
  const StepStability& check_stability();
  /// Check step stability now and, with the step control, choose the next step from it (as every
  /// settings().stability_interval steps), as if `interval` steps had passed since the last check.
  void check_and_control_step(int interval);

  /// Put this simulation into a saved state: its materials and walls (same order) must be those of the
  /// simulation the state came from; everything else is replaced. The next step continues exactly as
  /// the original would have, bit for bit. No setup() needed afterwards. Throws std::invalid_argument,
  /// leaving the simulation unchanged, if the state is inconsistent or does not fit the materials and
  /// walls.
  void restore(SimulationState&& state);
  /// For checkpoints: the id the next sphere will get, the neighbour skin in use, the wall contacts.
  std::uint64_t next_sphere_id() const { return next_sphere_id_; }
  double skin() const { return skin_; }
  const ForceField& force_field() const { return forces_; }
  /// Set up (time step chosen, forces computed)?
  bool ready() const { return ready_; }
  /// Whether the spheres hold their bodies' state now (a bed of loose spheres after a list build:
  /// SimulationSettings::loose_bodies_in_spheres); for tests and reports.
  bool loose_bodies_in_spheres() const { return spheres_hold_bodies_; }

  Energy energy() const;
  /// Bytes of particle, neighbour and contact data (memory report).
  std::size_t bytes() const;

 private:
  void check_pairs_in_use(const Particles& p) const;
  /// The skins for a build (dem/adaptive_skin.hpp): the common one and the largest (a fixed
  /// time.skin: that for both); where they differ, each sphere's own into own_skin_, in the present
  /// slot order.
  struct SkinChoice {
    double common = 0, largest = 0;
    int frame_wall = -1;  // the list's frame (dem/list_frame.hpp): a wall's, or the world's (-1)
  };
  /// The wall whose frame a list may be measured in: the first with a motion (-1 if none).
  int container_wall() const;
  /// The list's frame shift (dem/list_frame.hpp) for spheres at time t, its wall's pose then.
  FrameShift frame_shift_at(double t) const;
  SkinChoice choose_skins() const;
  /// A neighbour-list build with `skins`, chosen by choose_skins() just before (own_skin_ is theirs).
  void rebuild(const SkinChoice& skins);
  /// The skins of a build due before the list is stale (a thinner skin), if one is.
  std::optional<SkinChoice> early_rebuild() const;
  bool skin_check_due() const;  // whether early_rebuild may find one this step
  /// Forces, then the bodies' sums (with a half kick if > 0) in the same region; then the health check.
  void compute_forces(double half_kick);
  void check_health();
  std::uint64_t add_body(double mass, const Vec3& inertia, const Vec3& x, const Quat& q, const Vec3& v,
                         const Vec3& omega, int shape);
  void check_step_for(int material, double radius) const;
  const MassProperties& mass_properties_of(const Shape& shape);
  /// Thread `thread`'s part of the drift (half kick, drift, spheres follow), in a region of `team`;
  /// returns the largest squared displacement among its spheres (as follow_one gives it).
  double drift_part(int team, int thread, double dt, std::uint64_t epoch);
  /// Up to `most` steps in one parallel region; returns how many were done (at least one).
  std::uint64_t steps_in_region(std::uint64_t most);
  /// After the drift, by one thread of a team of `team` (steps_in_region).
  bool drifted(int team);
  void finish_step();
  /// The step the input sets: time.step, or time.step_fraction of the smallest Rayleigh time.
  double input_time_step() const;
  /// After a stability check: the step control's next step (dem/step_control.hpp), `interval`
  /// steps after the one before.
  void control_step(const StepStability& now, int interval);
  bool healthy() const;
  bool stability_due() const;
  void update_sphere_state() const;
  /// After the bodies' sums (with a half kick if `kicked`): what they leave behind (omega behind L,
  /// and where the spheres hold the bodies' state, the bodies' copy behind the spheres).
  void bodies_summed(bool kicked);
  /// Tell the force loop where the spheres' velocities are (ForceField::read_motion_from_bodies).
  void read_motions();
  /// The bodies' arrays brought up to date for a reader (update_body_copy, update_body_omega).
  void update_bodies() const;
  void update_body_omega() const;
  /// Where the spheres hold their bodies' state (spheres_hold_bodies_): the bodies' x, v, force and
  /// torque made from their spheres' (a cache, hence const; omega is made from L, update_body_omega).
  void update_body_copy() const;
  /// Whether every body is a loose sphere in the slot of its own index (body k is sphere k), as
  /// renumber_bodies leaves a bed of loose spheres.
  bool loose_spheres_in_order() const;
  void move_spheres_with_bodies();
  void index_spheres_by_body();
  void renumber_bodies();
  /// Thread team.thread()'s share of the bodies' sums (in the force loop's region: compute_forces),
  /// but for those sum_ready_bodies did already (`progress`).
  void sum_bodies(const ForceTeam& team, double half_kick, const AfterForces::Progress& progress);
  /// Of thread `thread`'s bodies, those whose spheres all lie in [from, to), the spheres whose
  /// forces are final so far (AfterForces::ready), and that it has not summed yet.
  void sum_ready_bodies(int team, int thread, std::size_t from, std::size_t to, double half_kick,
                        AfterForces::Progress& progress);
  /// Body k's sum of its spheres' forces and torques, plus gravity, and the half kick if half_kick > 0.
  void sum_body(std::size_t k, double half_kick);
  /// The bodies' sums as the force loop's follow-up (ForceField::compute, ForceField::pass).
  struct BodySums final : AfterForces {
    Simulation& sim;
    double half_kick;
    BodySums(Simulation& s, double h) : sim(s), half_kick(h) {}
    /// Only where bodies are clumps, two spheres or more on average: a clump's spheres lie scattered
    /// over a window of slots, and summed after the sweep they were read from memory at random (the
    /// platform box: in-process A/B +8 to +11 % on 1 thread, +3 to +6 % on 2). Loose spheres are
    /// summed after the sweep in one stream the hardware follows; in the sweep they added streams to
    /// its two dozen (the 10^5-sphere bed: -1 to -7 %).
    bool wants_ready() const override { return 2 * sim.bodies_.size() <= sim.particles_.size(); }
    void ready(int team, int thread, std::size_t from, std::size_t to, Progress& progress) override {
      sim.sum_ready_bodies(team, thread, from, to, half_kick, progress);
    }
    void run(const ForceTeam& team, Progress& progress) override { sim.sum_bodies(team, half_kick, progress); }
  };
  /// The bodies [first, last) thread t of a team of `team` takes in the per-body loops: those whose
  /// first sphere lies in the spheres it takes in the force loop (ForceField::thread_spheres).
  void thread_bodies(int team, int t, std::size_t& first, std::size_t& last) const;
  /// Of thread t's bodies [first, last) (bodies indexed by sphere), the first that may have spheres
  /// at or beyond its sphere range's end `sphere_last`: [result, last) cross into the ranges above.
  std::size_t first_crossing_body(int team, int t, std::size_t first, std::size_t last, std::size_t sphere_last) const;

  MaterialTable materials_;
  SimulationSettings settings_;
  Particles particles_;
  Bodies bodies_;
  std::vector<std::string> shape_names_;
  std::vector<Wall> walls_;
  NeighborList neighbors_;
  ForceField forces_;
  ForceDiagnostics diag_;
  StepStabilityMonitor stability_monitor_;
  StepStability stability_, worst_stability_;
  double time_ = 0, dt_ = 0, skin_ = 0;
  double dt_ceiling_ = 0, lowest_dt_ = 0;  // the input's step; the smallest taken (step control)
  std::uint64_t dt_changes_ = 0;
  std::uint64_t steps_ = 0, next_sphere_id_ = 0;
  double moved2_ = 0;  // largest squared sphere displacement since the last neighbour build
  // Scratch of choose_skins and rebuild (per sphere): the skins chosen, their speeds squared, the
  // skins in the new slot order.
  mutable std::vector<double> own_skin_, speed2_, skin_scratch_;
  mutable std::vector<double> frame_speed2_;  // each sphere's speed squared in the container's frame
  std::vector<std::uint32_t> body_fill_;  // scratch for index_spheres_by_body
  TeamSignals step_signals_;  // a step's waits: bodies that cross a cut (drift_part), the meets (steps_in_region)
  struct alignas(64) ThreadValue {
    double value = 0;
  };
  std::vector<ThreadValue> moved2_of_;  // each thread's largest displacement in the drift
  std::size_t body_slot_span_ = 0;        // the most slots between two spheres of one body (index_spheres_by_body)
  std::vector<std::uint32_t> body_order_, body_new_index_;  // scratch for renumber_bodies
  Renumbering renumbering_, body_renumbering_;  // a build's, of the spheres and of the bodies (the slots they move)
  /// Mass properties of each distinct sphere set added so far (mass_properties_of).
  std::vector<std::pair<std::vector<SphereComponent>, MassProperties>> mass_cache_;
  bool ready_ = false;
  mutable bool sphere_state_lags_ = false;  // the spheres' q, v, omega are behind their bodies'
  mutable bool body_omega_lags_ = false;    // the bodies' omega is behind their L (the kick leaves it)
  // A bed of loose spheres only, each body k the sphere in slot k (loose_spheres_in_order, checked at
  // each indexing): the step keeps the bodies' position, velocity and angular velocity in their
  // spheres' arrays, and takes their force and torque from their spheres' sums, instead of keeping a
  // copy in the bodies' arrays and copying it to the spheres every step (the follow) and back
  // (the sums). The bodies' arrays keep what only they hold: q, L, the masses and inertias. Their
  // x, v, force and torque are made from the spheres on demand (update_body_copy), their omega from
  // L (update_body_omega). The same numbers: a loose sphere's position is its body's, and its sums
  // are its body's (sum_body).
  bool spheres_hold_bodies_ = false;
  mutable bool body_copy_lags_ = false;  // the bodies' x, v, force, torque are behind their spheres'
};

}  // namespace grainscale::dem
