#pragma once
// Computes the contact forces and torques on every sphere for one step: sphere pairs from the
// neighbour list and sphere-wall contacts. (Bodies add gravity when they sum their spheres.) The loop is written once (force_field.cpp) and instantiated for each
// contact/rolling model pair; models are small evaluator structs in dem/contact/.
//
// One sweep over the spheres in blocks, with two fronts. The pair front runs over neighbour-list
// entries (owner slot in parallel): it sums the owner's share of its contacts and stores the
// partner's share by entry (in beds beyond the caches, mostly in a ring per thread that stays in
// the caches: share_ring_entries()); the touching pairs it finds are evaluated in batches, vectorised
// (dem/pair_batch.hpp), with the same numbers as one at a time. The completion front follows right
// behind (a pair's owner is its smaller slot, so a sphere the pair front has passed has met all its
// pairs) and adds, in that fixed order, the partner shares (through the sphere's reverse range of
// entries) and the wall contacts, while what it reads is still in the caches. Beds within the caches
// complete every block in a second loop instead (the same sums).
// Most entries of a bed are not in contact (the skin): a one-byte flag per entry says which shares
// are current, so both fronts touch nothing but that flag for them (the per-entry traffic
// bounded the step: docs/performance.md). No two threads write the same memory, so results are
// bitwise identical for any thread count.
#include <cstdint>
#include <limits>
#include <variant>
#include <vector>

#include "dem/contact/hertz_mindlin.hpp"
#include "dem/contact/rolling_constant_torque.hpp"
#include "dem/contact/rolling_epsd.hpp"
#include "dem/contact/rolling_none.hpp"
#include "dem/material.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/particles.hpp"
#include "dem/rolling_model.hpp"
#include "dem/uninitialized_array.hpp"
#include "dem/wall.hpp"
#include "dem/team_signals.hpp"
#include "dem/wall_slots.hpp"
#include "dem/work_split.hpp"

namespace grainscale::dem {

template <class Rolling>
struct PairBatch;
template <class Rolling>
struct WallBatch;

/// Worst state seen while computing forces; used by the blow-up check.
struct ForceDiagnostics {
  double max_overlap_ratio = 0;  // max over contacts of overlap / smaller radius
  // max over contacts of omega dt, omega = sqrt(S_n / m*) the contact's normal oscillation frequency
  // at its current overlap: the step resolves a contact only while this stays well below 1
  double max_omega_dt = 0;
  std::int64_t bad_slot = -1;    // first slot with a non-finite force or torque, or -1
  std::int64_t slot_overflow = -1;  // first slot with more wall contacts than kWallSlots
  std::size_t contacts = 0;      // particle-particle contacts in force
  std::size_t wall_contacts = 0;
};

struct ContactEnergy {
  double normal = 0;      // elastic energy in normal springs, J
  double tangential = 0;  // 1/2 S_t |s|^2 summed (approximate: Mindlin stiffness varies), J
};

/// Contact and rolling parameters for every material pair, [a * materials + b].
template <class Rolling>
struct ContactModels {
  int materials = 0;
  std::vector<HertzMindlin::Params> contact;
  std::vector<typename Rolling::Params> rolling;
};

/// Beds of this many spheres or more are taken to be beyond the caches: the pair front then
/// prefetches partners and tests a chunk of entries before gathering its contacts, and the
/// completion front follows it (dem/force_field.cpp). Either way gives the same numbers, bit for
/// bit; tests set 0 to run the chunked loop and the completion front on small beds (as
/// parallel_min_items, dem/parallel.hpp, makes small loops parallel).
inline std::size_t& beyond_cache_spheres() {
  static std::size_t spheres = 50000;
  return spheres;
}

/// In beds beyond the caches each thread keeps the partner shares its completion front reads in a
/// ring of this many entries (a power of two, at least 256; 0: none), not in the array of one share
/// per list entry: the front reads a share back a few thousand entries after the pair front stored
/// it, so the ring stays in the caches, where each store to the array waited for its line from
/// memory. Shares the ring cannot hold until they are read go to the array (ForceField::share_ring_
/// says which). The same numbers either way; tests set small rings to make the array's part large.
inline std::size_t& share_ring_entries() {
  static std::size_t entries = 8192;
  return entries;
}

/// The threads of the force loop's team as one of them sees them once its own spheres' forces are
/// complete: what it must wait for before it reads other spheres' forces (dem/team_signals.hpp).
class ForceTeam {
 public:
  ForceTeam(const TeamSignals& signals, std::uint64_t epoch, int team, int thread)
      : signals_(signals), epoch_(epoch), team_(team), thread_(thread) {}
  int size() const { return team_; }
  int thread() const { return thread_; }
  /// Returns once the threads above this one have completed their spheres' forces.
  void wait_above() const {
    for (int t = thread_ + 1; t < team_; ++t) signals_.wait(t, epoch_);
  }
  /// Returns once every thread has (its spheres anywhere: an equal share of bodies).
  void wait_all() const {
    for (int t = 0; t < team_; ++t) signals_.wait(t, epoch_);
  }

 private:
  const TeamSignals& signals_;
  std::uint64_t epoch_;
  int team_, thread_;
};

/// Work that follows the forces in the force loop's parallel region, by each thread (the bodies'
/// sums, dem/simulation.cpp): one fork and join a step fewer (3.2-3.7 µs on this project's VMs), and
/// a thread starts on it as soon as its own forces are done.
///
/// In beds beyond the caches the sweep also says, block by block, which of the thread's spheres have
/// their final force already (ready): work on those done there reads their forces while they are
/// still in the caches, instead of from memory after the sweep (the platform box's body sums: 10 %
/// of its step, waiting on those loads; docs/performance.md). `progress` is the follow-up's own note
/// of what it has done, kept by the force loop for it, one per thread; run() does the rest.
class AfterForces {
 public:
  struct Progress {
    bool started = false;
    std::size_t first = 0, next = 0, stop = 0;  // for the follow-up's use
  };
  /// Whether ready() is to be called this step at all.
  virtual bool wants_ready() const = 0;
  /// Spheres [from, to) of this thread's range have their final forces; `from` is the same in every
  /// call of a step, `to` grows. Not called in beds within the caches.
  virtual void ready(int team, int thread, std::size_t from, std::size_t to, Progress& progress) = 0;
  virtual void run(const ForceTeam& team, Progress& progress) = 0;

 protected:
  ~AfterForces() = default;
};

class ForceField {
 public:
  static constexpr int kWallSlots = WallSlots::kSlots;

  void setup(const MaterialTable& materials, const std::vector<Wall>& walls, const RollingSettings& rolling);
  /// Every sphere's contact force and torque, and then `after` (if any) by each thread of the team.
  /// begin(), a parallel region in which every thread runs pass(), then finish().
  ForceDiagnostics compute(Particles& p, NeighborList& nl, const std::vector<Wall>& walls, double dt,
                           AfterForces* after = nullptr);
  /// compute() in its three parts, for a caller with a parallel region of its own (Simulation's
  /// steps): begin() by one thread while the team waits for it; pass() by each of the `team`
  /// threads; finish() by one thread once all have passed (it combines their diagnostics).
  void begin(Particles& p, NeighborList& nl, const std::vector<Wall>& walls, int team);
  void pass(int team, int thread, Particles& p, NeighborList& nl, const std::vector<Wall>& walls, double dt,
            AfterForces* after);
  ForceDiagnostics finish(double dt);
  /// True if begin() would run no loop over the spheres or entries and allocate nothing, so that one
  /// thread may run it inside a region while the others wait: the list used before (no build
  /// since), the walls within their masks' margins, room for a team of `team`.
  bool begins_in_team(const Particles& p, const NeighborList& nl, const std::vector<Wall>& walls, int team) const;
  /// Renumber the per-particle wall histories with the particles.
  void permute(const Renumbering& r);
  /// Room for the wall contacts of n particles (those of the first min(n, before) kept).
  void resize(std::size_t n);
  /// Wall-contact histories: kWallSlots per particle slot, of which the first wall_counts()[i] are
  /// in use (the rest are never read). What a checkpoint stores (dem/checkpoint.hpp).
  const WallSlot& wall_slot(std::size_t i, int s) const { return wall_slots_.now(i, s); }
  const std::vector<std::uint8_t>& wall_counts() const { return wall_slots_.counts_vector(); }
  /// Reinstate them for `counts.size()` particles from the slots in use only, particle by particle
  /// (`used.size()` == sum of `counts`), each naming one of `walls` walls. Throws
  /// std::invalid_argument (nothing changed) if they do not fit.
  void restore_wall_contacts(const std::vector<std::uint8_t>& counts, const std::vector<WallSlot>& used,
                             std::size_t walls);
  /// Hertz-Mindlin parameters of the material pair (a, b), as the force loop uses them.
  const HertzMindlin::Params& contact_params(int a, int b) const {
    return std::visit([&](const auto& m) -> const HertzMindlin::Params& { return m.contact[a * m.materials + b]; },
                      models_);
  }
  ContactEnergy contact_energy(const Particles& p, const NeighborList& nl, const std::vector<Wall>& walls) const;
  /// The rigid bodies' centres, velocities and angular velocities, by body index (p.body).
  struct BodyMotion {
    const Vec3 *x = nullptr, *v = nullptr, *omega = nullptr;
    /// The velocity of body k's point at xs: v_k + omega_k x (xs - x_k).
    Vec3 velocity_at(std::uint32_t k, const Vec3& xs) const { return v[k] + cross(omega[k], xs - x[k]); }
  };
  /// Where the force loop reads sphere s's velocity and angular velocity: p.v[s] and p.omega[s]
  /// (motion.x null, the default), or from its rigid body k = p.body[s]: omega_s = omega_k, v_s =
  /// v_k + omega_k x (x_s - x_k). A sphere of a clump moves with its body, so the drift need not
  /// copy them into every sphere: 48 of the 72 bytes it stored per sphere-step (Simulation, which
  /// sets this before each force evaluation). The lever x_s - x_k rounds differently from the
  /// rotated offset the position was made from (a relative 1e-16 of the velocity).
  void read_motion_from_bodies(const BodyMotion& motion) { body_motion_ = motion; }
  /// The last compute()'s rings of partner shares: entries per thread (0: none), and how far a pair
  /// may reach (partner - owner, in slots) and keep its share there (share_ring_entries()).
  std::size_t share_ring_size() const { return ring_entries_; }
  std::uint32_t share_ring_reach() const { return ring_entries_ > 0 ? ring_reach_ : 0; }
  std::size_t bytes() const;

  /// The spheres [first, last) of `n` that thread t of a team of `team` takes in the force loop: its
  /// range of the split cut by cost (dem/work_split.hpp), or an equal share of the blocks when no
  /// split fits the team and the sphere count. The other per-sphere and per-body loops of a step take
  /// the same ranges (Simulation::thread_bodies), so that a sphere's state stays on one core.
  void thread_spheres(std::size_t n, int team, int t, std::size_t& first, std::size_t& last) const;

  /// How far, in skins (NeighborList::skin), a wall that moves in the list's frame may travel against
  /// the spheres between one making of the near-wall masks and the next (find_near_walls).
  static constexpr double kMovingWallMargin = 0.5;
  /// The near-wall masks the last compute() made, per particle slot, while they hold: made for this
  /// list (no build since) and these `n` particles, and `walls` not moved beyond their margins since;
  /// else nullptr. Lets other per-contact loops (the step-stability monitor) skip walls out of reach
  /// as the force loop does, finding the same contacts.
  const std::uint32_t* near_wall_masks(const std::vector<Wall>& walls, const NeighborList& nl, std::size_t n) const {
    const bool hold = list_generation_ == nl.generation() && near_walls_.size() == n && walls_where_found(walls, nl.frame());
    return hold ? near_walls_.data() : nullptr;
  }
  /// True if `masks` (from near_wall_masks, may be null) rule out any contact of particle i with wall w.
  static bool out_of_reach(const std::uint32_t* masks, std::size_t i, std::size_t w) {
    return masks != nullptr && w < kMaskedWalls && !(masks[i] >> w & 1u);
  }
  /// True if `masks` rule out any contact of particle i with all `walls` walls.
  static bool all_out_of_reach(const std::uint32_t* masks, std::size_t i, std::size_t walls) {
    return masks != nullptr && walls <= kMaskedWalls && masks[i] == 0;
  }

 private:
  template <class Rolling>
  using Models = ContactModels<Rolling>;
  using AnyModels = std::variant<Models<NoRolling>, Models<ConstantTorqueRolling>, Models<EpsdRolling>>;

  template <class Rolling>
  void begin_with(const Models<Rolling>& m, Particles& p, NeighborList& nl, const std::vector<Wall>& walls, int team);
  template <class Rolling>
  void pass_with(const Models<Rolling>& m, int team, int thread, Particles& p, NeighborList& nl,
                 const std::vector<Wall>& walls, double dt, AfterForces* after);
  /// A thread's part of the diagnostics of one pass (finish() combines them), a line each.
  struct alignas(64) PassStats {
    std::size_t contacts = 0, wall_contacts = 0;
    double worst_ratio = 0, stiff_pair = 0, worst_wall = 0, stiff_wall = 0;
    std::int64_t bad = std::numeric_limits<std::int64_t>::max(), overflow = std::numeric_limits<std::int64_t>::max();
  };
  std::vector<PassStats> pass_stats_;
  int pass_team_ = 1;                                // the team of the last pass (set by its thread 0)
  std::uint64_t pairs_done_ = 0, forces_done_ = 0;  // its epochs (signals_)

  /// What a pair contact puts on its partner j: -force and torque (indexed by entry).
  struct PartnerShare {
    Vec3 force, torque;
  };
  /// Sums of the owner's shares of the sphere whose batched contacts are being added (the pair front).
  struct OwnerSum {
    std::size_t slot;  // >= the sphere count: none yet
    Vec3 force{}, torque{};
  };
  template <class Rolling>
  void flush_pairs(PairBatch<Rolling>& b, double dt, Particles& p, NeighborList& nl, OwnerSum& open,
                   double& worst_ratio, double& stiff_pair, PartnerShare* ring, std::uint32_t ring_mask);

  /// The wall contacts' part of the step's diagnostics, per thread.
  struct WallStats {
    std::size_t contacts = 0;
    std::int64_t overflow = std::numeric_limits<std::int64_t>::max();
    double worst_ratio = 0, stiffness_per_mass = 0;
  };
  /// Sphere i's wall contacts (its force and torque so far already stored): found, their histories
  /// matched, queued in `batch` (evaluated and added to the sphere by flush_walls).
  template <class Rolling>
  void add_wall_contacts(const Models<Rolling>& m, Particles& p, const std::vector<Wall>& walls, std::size_t i,
                         double dt, WallBatch<Rolling>& batch, WallStats& ws, std::int64_t& bad);
  template <class Rolling>
  void flush_walls(WallBatch<Rolling>& batch, double dt, Particles& p, WallStats& ws, std::int64_t& bad);

  AnyModels models_;
  std::vector<int> wall_material_;
  BodyMotion body_motion_;  // read_motion_from_bodies
  std::vector<PartnerShare> partner_share_;
  // The rings of partner shares (share_ring_entries()), ring_entries_ per thread, in beds beyond the
  // caches; ring_entries_ 0 when none is used. An entry's share is kept in its thread's ring, at
  // [entry & (ring_entries_ - 1)], if its pair is touching, its partner j is completed by the
  // thread's completion front (not left for after the threads below, nor beyond the thread's range),
  // and j - i <= ring_reach_ (i its owner): the bit kInRing of touching_[entry] says so. With that
  // reach, no ring slot is stored again before the share in it is read (pass_with's guard).
  static constexpr std::uint8_t kInRing = 2;
  std::vector<PartnerShare> share_ring_;
  std::size_t ring_entries_ = 0;
  std::uint32_t ring_reach_ = 0;
  std::uint64_t ring_generation_ = ~std::uint64_t{0};
  /// Chooses this step's ring and its reach (begin_with; a loop over the spheres at a new list).
  void choose_ring(const NeighborList& nl, std::size_t n, int team);
  bool ring_chosen(const NeighborList& nl, std::size_t n, int team) const;
  // touching_[k]: entry k was in contact at the last compute, so its history may be non-zero and
  // its partner share is current (in partner_share_[k], or in a ring if bit kInRing is set too). Invariant: touching_[k] == 0 implies a zero history, so a pair
  // that stays apart costs no writes to its history (the entry loop for beds in the caches writes
  // nothing for it at all). Rebuilt from the histories when the list changes (generation).
  std::vector<std::uint8_t> touching_;
  // Which thread takes which blocks of the force loop (dem/work_split.hpp): split by block_cost_,
  // estimated again at each list build and when the near-wall masks are made again (split_stale_).
  WorkSplit work_split_;
  // The force loop's waits: a thread completes its first spheres once those below have posted their
  // pairs, and the follow-up reads other threads' spheres once they have posted their forces.
  TeamSignals signals_;
  /// The blocks [first, last) thread t of a team of `team` takes (see thread_spheres).
  void thread_blocks(std::size_t n, int team, int t, std::size_t& first, std::size_t& last) const;
  std::vector<double> block_cost_;
  bool split_stale_ = true;
  std::uint64_t list_generation_ = ~std::uint64_t{0};
  // near_walls_[i] bit w: wall w (w < kMaskedWalls) may touch sphere i before the masks are made
  // again: at each list build, and when a wall has moved further than its margin (find_near_walls
  // says how). The profile had a box wall's distance test at 4 % of a settled clump bed, and a moving
  // mesh box's at a third of the default study, for spheres nowhere near it.
  static constexpr std::size_t kMaskedWalls = 32;
  std::vector<std::uint32_t> near_walls_;
  std::vector<WallPose> mask_poses_;    // the walls' poses when the masks were made
  std::vector<double> mask_margin_;     // and their margins (0: static)
  Vec3 mask_region_lo_, mask_region_hi_;  // box around the spheres (strays aside) then, in the list's frame
  int mask_frame_wall_ = -1;              // the list's frame then (its pose: mask_poses_[it])
  // Each sphere's hint for each wall whose geometry uses one (WallGeometry::Hint): wall_hints_[i *
  // hinted_walls_ + hint_index_[w]], hint_index_[w] -1 for a wall without. A hint is checked on use
  // (the mesh's names its cell), but belongs to its wall's geometry: walls are only appended, so
  // wall w keeps its geometry. Set to kNoHint at every list build by find_near_walls.
  std::vector<WallGeometry::Hint> wall_hints_;
  std::vector<int> hint_index_;
  std::size_t hinted_walls_ = 0;
  /// at_build: the list was just built, so every sphere is where the list has it.
  void find_near_walls(const Particles& p, const std::vector<Wall>& walls, const NeighborList& nl, bool at_build);
  bool walls_where_found(const std::vector<Wall>& walls, const ListFrame& frame) const;
  /// Whether wall w may move in the list's frame: it has a motion, or the frame is a moving wall's
  /// (the frame's own wall then moves with it, but is not told apart: its shift is 0 to round-off).
  static bool moves_in_frame(const Wall& w, const ListFrame& frame) { return w.moving() || frame.in_wall(); }
  /// Some wall may touch sphere i before the masks are made again (of `walls` walls).
  /// (`|`, not `||`: both operands are cheap, and no branch is needed where a loop counts or lists.)
  bool wall_in_reach(std::size_t i, std::size_t walls) const { return (near_walls_[i] != 0) | (walls > kMaskedWalls); }
  // Wall-contact histories, this step's and last step's (double buffer: no copy of a sphere's old
  // slots, which perf showed stalling on the stores it had just made), slot-major: dem/wall_slots.hpp.
  WallSlots wall_slots_;
};

}  // namespace grainscale::dem
