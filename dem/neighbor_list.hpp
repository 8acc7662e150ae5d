#pragma once
// Cell list with a Verlet skin (Allen & Tildesley 2017, Sec. 5.3-5.4).
//
// * Particles are binned in cubic cells of edge >= 2 r_max + skin and renumbered in cell order,
//   so that particles close in space are close in memory. Cells are numbered with the axis of fewest
//   cells fastest and the axis of most cells slowest: a particle's neighbours then lie within
//   2 n_fast n_mid cells of it in slot order (the window the force loop streams through). For a flat
//   bed 3 cells deep and 430 x 430 cells wide that is 2,600 cells, where z-slowest order would make it
//   370,000 - a third of the bed, far beyond the caches (bench/run_scaling.sh, docs/performance.md).
// * The list is a half list stored as CSR: pair {a, b} is stored once, under the particle with the
//   smaller slot, if |x_a - x_b| < r_a + r_b + skin and a, b belong to different bodies. So every
//   entry's partner comes after its owner, and once the force loop has passed slot s, every pair
//   of a particle before s has been met: the force loop completes each particle's force right
//   behind its front, while the particle is still in the caches (dem/force_field.hpp). A rebuild
//   renumbers the particles, and a pair whose owner changes carries its history negated (the
//   history of the pair seen from the other particle: exact). (Until 2026-12-05 the owner was the
//   particle with the smaller id; restore() re-keys a list saved then.)
// * Strays (grains thrown out of an open container, falling away) do not stretch the grid: when the
//   bounding box would need more than 8 cells per particle, the grid covers the 1st-99th percentile
//   of the positions on each axis and the rest fall into its edge cells; the list stays exact.
// * Each particle may have a skin of its own, s_i (the adaptive skin gives the few fast particles
//   of a bed at rest thicker ones: dem/adaptive_skin.hpp): pair {a, b} is listed if
//   |x_a - x_b| < r_a + r_b + (s_a + s_b)/2, and the list stays exact while every particle has moved
//   less than its own s_i/2 since the build (a pair not listed was (s_a + s_b)/2 beyond touching, and
//   its gap has closed by at most the two displacements). With one skin for all this is the usual
//   rule: pairs within r_a + r_b + skin, valid until some particle has moved skin/2. A stray far from
//   everything may move further (its slack, assign_stray_slack), so one falling away from an open
//   container does not force a build every step.
// * Each entry carries the contact history; a rebuild carries histories over to the new entries.
//   The history is kept as two arrays, the tangential spring and the rolling spring, because only
//   rolling models with a spring (EPSD) use the second: the force loop of the others (the report's
//   constant torque) then streams half the history bytes per entry (docs/performance.md).
// * A reverse CSR lists, for every particle, the entries where it is the partner, so forces can be
//   gathered per particle in a fixed order: deterministic for any thread count, no atomics.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dem/contact/contact_kinematics.hpp"
#include "dem/list_frame.hpp"
#include "dem/particles.hpp"

namespace grainscale::dem {

class NeighborList {
 public:
  /// New slot order (new_to_old) sorting particles by cell. Also prepares the cell grid for build().
  /// Throws std::overflow_error if a position or the particles' extent is not finite (a blown-up state).
  const std::vector<std::uint32_t>& sort_by_cell(const Particles& p, double skin);

  /// Build the list for particles already renumbered by sort_by_cell()'s order; `new_to_old` maps the
  /// new slots to the slots of the previous build so histories can be carried over. Particles appended
  /// since the previous build (slots beyond its count) start without history. One skin for all
  /// (it must not exceed the skin the cells were sorted for).
  void build(Particles& p, double skin, const std::vector<std::uint32_t>& new_to_old);
  /// The same with a skin per particle, in the new slot order (p.size() of them, each finite, >= 0
  /// and at most the skin the cells were sorted for).
  void build(Particles& p, const std::vector<double>& skins, const std::vector<std::uint32_t>& new_to_old);
  /// For every particle (new slot order, after sort_by_cell): the largest of `own` over the particles
  /// of its own cell and the adjacent ones, into `out` (both p.size(); `floor`: the smallest value
  /// of `own`, which most particles hold: only those above it are spread). A particle about to be
  /// struck by a fast neighbour then gets the neighbour's skin (dem/adaptive_skin.hpp).
  void spread_to_adjacent_cells(const Particles& p, const std::vector<double>& own, double floor,
                                std::vector<double>& out) const;

  /// True once some particle has moved more than skin/2 since the last build, given the largest
  /// squared displacement since the build (computed by the caller inside its drift loop), or if the
  /// particle count has changed.
  /// The caller's displacement is d_i² − slack2()[i] (slack2 may be empty: all zero).
  bool stale(const Particles& p, double max_displacement2) const {
    return start_.size() != p.size() + 1 || max_displacement2 > 0.25 * skin_ * skin_;
  }
  /// The frame the caller measures the displacements in (dem/list_frame.hpp): a particle has moved
  /// |x - frame().shift_to(P)(x_at_build)|, P the frame wall's pose now. Set by the caller at each
  /// build; the list itself builds from world positions.
  const ListFrame& frame() const { return frame_; }
  void set_frame(const ListFrame& f) { frame_ = f; }
  /// Per slot of the last build: how much more than skin²/4 particle i's squared displacement may
  /// grow before the list is stale: s_i²/4 - skin²/4 (<= 0) for a particle of a thinner skin than the
  /// largest, more for a stray (its slack). Empty when every particle's is 0.
  const std::vector<double>& slack2() const { return slack2_; }

  std::uint32_t begin(std::size_t i) const { return start_[i]; }
  std::uint32_t end(std::size_t i) const { return start_[i + 1]; }
  std::uint32_t rev_begin(std::size_t i) const { return rev_start_[i]; }
  std::uint32_t rev_end(std::size_t i) const { return rev_start_[i + 1]; }
  std::uint32_t rev_entry(std::uint32_t r) const { return rev_entry_[r]; }
  /// Where entry k sits in its partner's reverse range: rev_entry(rev_position(k)) == k.
  std::uint32_t rev_position(std::uint32_t k) const { return rev_position_[k]; }
  std::uint32_t partner(std::uint32_t k) const { return partner_[k]; }
  /// The particle whose row holds entry k: begin(owner(k)) <= k < end(owner(k)).
  std::uint32_t owner(std::uint32_t k) const { return owner_[k]; }
  /// 1 + the furthest partner of the rows before slot s (0 if none; s <= the particle count): the
  /// particles of slots [s, reach_before(s)) are the only ones at or after s with pairs owned before s.
  std::uint32_t reach_before(std::size_t s) const { return reach_[s]; }
  /// The particle whose reverse range holds position r: rev_begin(i) <= r < rev_end(i) for i = rev_owner(r).
  std::uint32_t rev_owner(std::uint32_t r) const { return rev_owner_[r]; }
  /// Entry k's tangential (Mindlin) spring and rolling (EPSD) spring.
  Vec3& shear(std::uint32_t k) { return shear_[k]; }
  const Vec3& shear(std::uint32_t k) const { return shear_[k]; }
  /// (rolling(k) only while keeps_rolling_springs(); history(k) always, a zero rolling spring else.)
  Vec3& rolling(std::uint32_t k) { return rolling_[k]; }
  const Vec3& rolling(std::uint32_t k) const { return rolling_[k]; }
  ContactHistory history(std::uint32_t k) const { return {shear_[k], rolling_springs_ ? rolling_[k] : Vec3{}}; }
  /// Whether entries carry a rolling spring (the default). The force loop of a rolling model without
  /// one turns it off: the array is dropped (a rolling spring left by a model that has one, as a
  /// checkpoint of an EPSD run restarted under another model, with it) and no build fills it; the
  /// 2 x 24 bytes per entry it held were ~9 % of a settled bed's memory. Turned on, every entry's
  /// rolling spring starts at zero.
  bool keeps_rolling_springs() const { return rolling_springs_; }
  void keep_rolling_springs(bool keep);
  std::size_t entries() const { return partner_.size(); }
  std::size_t builds() const { return builds_; }
  /// Changes whenever the entries change (build or restore); never saved. Lets per-entry data kept
  /// elsewhere (the force field's contact flags) know when to rebuild itself.
  std::uint64_t generation() const { return generation_; }
  /// The largest skin of the last build (the only one when all particles share it).
  double skin() const { return skin_; }
  /// The smallest skin of the last build (the skin most particles of a bed at rest hold).
  double smallest_skin() const { return smallest_skin_; }
  /// Per slot of the last build, each particle's skin; empty when all share skin().
  const std::vector<double>& skins() const { return skins_; }
  /// Edge of the cells of the last sort_by_cell (2 r_max + skin unless a sparse cloud widened them).
  double cell_size() const { return cell_; }

  /// The list as built, in CSR form (entries of slot i are [starts()[i], starts()[i+1])), and each
  /// entry's contact history: what a checkpoint stores (dem/checkpoint.hpp).
  const std::vector<std::uint32_t>& starts() const { return start_; }
  const std::vector<std::uint32_t>& partners() const { return partner_; }
  std::vector<ContactHistory> histories() const;  // a copy, entry by entry
  /// The reverse index and the entries' owners as arrays (the force loop reads them through plain
  /// pointers).
  const std::vector<std::uint32_t>& rev_starts() const { return rev_start_; }
  const std::vector<std::uint32_t>& rev_entries() const { return rev_entry_; }
  const std::vector<std::uint32_t>& owners() const { return owner_; }
  /// Per reverse position r: the particle whose reverse range holds it (the partner of rev_entry(r)).
  const std::vector<std::uint32_t>& rev_owners() const { return rev_owner_; }
  Vec3* shear_data() { return shear_.data(); }
  Vec3* rolling_data() { return rolling_.data(); }
  /// Reinstate a list saved from starts(), partners() and histories() for particles `p` in the slot
  /// order they had then (plus any added since, at the end); the reverse index is rebuilt from it. The next build() carries the
  /// histories over exactly as it would have from the original list. A list keyed on id (saved
  /// before 2026-12-05) is re-keyed on slot, histories negated where a pair changes owner. Throws
  /// std::invalid_argument (nothing changed) if the arrays are not a valid half list for `p`.
  /// `skins`: the per-particle skins of skins() (empty: all `skin`; else one per row of the list, each
  /// finite, >= 0 and at most `skin`).
  void restore(const Particles& p, double skin, std::vector<double> skins, std::vector<std::uint32_t> start,
               std::vector<std::uint32_t> partner, const std::vector<ContactHistory>& history, std::size_t builds);
  /// Bytes held by the list (for memory reports).
  std::size_t bytes() const;

 private:
  /// The gridded box: all positions, or their 1st-99th percentile core when strays stretch them.
  struct GridBounds {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    double r_max = 0, cell = 0, max_cells = 0;
    bool trimmed = false;  // some particles lie outside [lo, hi]
    /// Cells along x, y, z for cells of edge c over [lo, hi] (in double: a particle flung far away
    /// would overflow an int).
    std::array<double, 3> cells_along(double c) const {
      return {std::floor((hi[0] - lo[0]) / c) + 1, std::floor((hi[1] - lo[1]) / c) + 1, std::floor((hi[2] - lo[2]) / c) + 1};
    }
    static double product(const std::array<double, 3>& f) { return f[0] * f[1] * f[2]; }
    /// Squared distance from x to the box (0 inside).
    double distance2(const Vec3& x) const {
      const double u[3] = {x.x, x.y, x.z};
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double out = std::max({lo[a] - u[a], u[a] - hi[a], 0.0});
        d2 += out * out;
      }
      return d2;
    }
  };
  static constexpr std::size_t kMaxStrays = 64;
  GridBounds grid_bounds(const std::vector<Vec3>& x, const std::vector<double>& radius, std::size_t n, double skin);
  void assign_stray_slack(const Particles& p, std::size_t n, const GridBounds& b);
  /// build()'s work once skin_, smallest_skin_ and skins_ are set.
  void build_rows(Particles& p, const std::vector<std::uint32_t>& new_to_old);
  int cell_of(const Vec3& x) const;
  void index_partners(std::size_t n);

  // Cell grid of the current build.
  Vec3 origin_;
  double cell_ = 0;
  int n_[3] = {0, 0, 0};     // cells along the fast, middle and slow axis of the numbering
  int axis_[3] = {0, 1, 2};  // world axis (0 x, 1 y, 2 z) of the fast, middle and slow axis
  std::vector<std::uint32_t> cell_start_;  // particles of cell c are slots [cell_start_[c], cell_start_[c+1])
  std::vector<int> cell_index_;            // per old slot, during sort
  std::vector<std::uint32_t> order_;       // new_to_old
  std::vector<double> scratch_;            // one coordinate per particle, for the core's percentiles
  GridBounds bounds_;                      // of the last sort_by_cell (or restore)
  std::vector<double> slack2_;             // per slot (empty: none); see slack2()
  std::vector<std::uint32_t> outside_, candidates_;  // scratch of assign_stray_slack
  std::vector<std::vector<std::uint32_t>> thread_partners_;  // scratch of build: partners per thread

  std::vector<std::uint32_t> start_, partner_, count_;
  std::vector<Vec3> shear_, rolling_;  // per entry: see shear(), rolling() (empty without rolling springs)
  bool rolling_springs_ = true;
  std::vector<std::uint32_t> old_start_, old_partner_;
  std::vector<Vec3> old_shear_, old_rolling_;
  std::vector<std::uint32_t> rev_start_, rev_entry_, rev_position_, rev_fill_;
  std::vector<std::uint32_t> owner_;      // per entry: its row (the force loop walks entries, not rows)
  std::vector<std::uint32_t> rev_owner_;  // per reverse position: its particle
  std::vector<std::uint32_t> reach_;      // per slot, and one past the last: see reach_before()
  double skin_ = 0, smallest_skin_ = 0;
  std::vector<double> skins_;  // per slot; empty: all skin_
  std::size_t builds_ = 0;
  ListFrame frame_;
  std::uint64_t generation_ = 0;
};

}  // namespace grainscale::dem
