#include "dem/parallel.hpp"
#include "dem/force_field.hpp"
#include "dem/pair_batch.hpp"
#include "dem/prefetch.hpp"
#include "dem/wall_batch.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace grainscale::dem {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The pair front fetches the partner of the entry kPrefetchEntries ahead (its position, radius,
// velocities, mass, moment of inertia and material: all that `gather` reads of it) in beds too
// large for the caches: there its neighbours in the next rows of cells stream from memory and the
// hardware prefetchers, with a dozen arrays to follow at two or three distances each, miss them. In
// beds that fit the caches the prefetches only cost (10^4 spheres -4 %, the clump bed -2 %; measured
// 2026-12-04, when they were still compiled in: dem/prefetch.hpp), hence the threshold: 10^4
// spheres (16 MB) fit a 32 MiB L3, 10^5 (160 MB) do not (beyond_cache_spheres(), which also picks
// the entry loop and the completion front: see there).
// In-process A/B (2026-12-06, fifteenth session, 1 thread), the partner prefetch left out: the
// platform box mid-rise -8 / -15 %, the 10^5 bed -1 to -4 %. 12 and 48 entries ahead: level.
// Its mass, inertia and material too (sixteenth session; until then only the first four, and the
// load of material[j] had 6 % of the pass's samples in the platform box): in-process A/B, the
// platform box mid-rise +7.3, +5.3, +7.8, +3.8 % on 1 thread, +1.2 to +3.6 % on 2, at the tilt's
// start +5.6, +3.9 %; the 10^5 bed +2.3, -0.6 % (its partners mostly lie within the block prefetch).
constexpr std::size_t kPrefetchEntries = 24;
// ... and, at the start of each block, every line of the block `prefetch_blocks` ahead in the
// arrays it walks in order (the spheres' state and sums, its entries and their histories, its reverse
// range). A hardware prefetcher follows a stream only within a 4 KiB page and the pass walks some 25
// streams, so each stream would pay its first lines of every page at full latency (a microbenchmark
// pays 3 ns a line over 8 streams, 6-9 over 28-40: docs/performance.md, "ninth session"). How far
// ahead: about kPrefetchBytes of those lines, so that the lines requested are still in the caches
// when the pass comes to them, and far enough for the partners of most pairs. In-process A/B
// (fifteenth session, 1 thread, against 8 blocks ahead): the 10^5 bed (2 entries a sphere, 15 KB a
// block) 6, 12 and 16 blocks -1.7, -1.8 and -2.8 %; the platform box (0.73 entries, 12 KB a block)
// 12 and 16 blocks +8.8 and +7.6 % mid-rise, 12 +12 % at rest; without the block prefetch the 10^5
// bed -3 %, the platform box -1 %.
constexpr double kPrefetchBytes = 128 * 1024;

// The chunked entry loop (beds beyond the caches) tests this many entries before gathering its contacts.
constexpr std::uint32_t kEntryChunk = 128;

constexpr std::size_t kPassBlock = 64;  // spheres per block (a thread takes a range of blocks: dem/work_split.hpp)
// What a block costs the force loop, per sphere, per list entry it owns and per sphere near a wall
// (perf, the 10^3 bed, 1 thread: ~4 ns a sphere, ~20 ns an entry, ~25 ns a sphere with a wall in
// reach); the split's feedback corrects what this estimate misses.
constexpr double kSphereCost = 1, kEntryCost = 5, kWallSphereCost = 6;

/// The blocks ahead of the pass whose lines prefetch_block requests: as many as kPrefetchBytes holds,
/// for a list of `entries` entries over `n` spheres (bytes a sphere and an entry as prefetch_block
/// has them, but for `start` of the block a distance farther, 4 bytes a sphere, added after these
/// distances were measured and left out so as not to move them): 8 on the 10^5 bed, 11 in the
/// platform box.
std::size_t prefetch_blocks(std::size_t n, std::size_t entries, bool rolling_springs) {
  const double sphere = 3 * sizeof(Vec3) + 3 * sizeof(double) + sizeof(std::int32_t) + 2 * sizeof(Vec3) + 2 +
                        sizeof(std::uint32_t);  // x v omega, radius mass inertia, material, force torque, counts, rev_start
  const double entry = 2 * sizeof(std::uint32_t) + 1 + (rolling_springs ? 2 : 1) * sizeof(Vec3) +
                       2 * sizeof(std::uint32_t);  // owner partner, flag, springs, reverse entry and owner
  const double block = kPassBlock * (sphere + entry * static_cast<double>(entries) / static_cast<double>(std::max<std::size_t>(n, 1)));
  return std::clamp(static_cast<std::size_t>(kPrefetchBytes / block), std::size_t{4}, std::size_t{32});
}

/// How far (partner - owner, in slots) a pair may reach and keep its partner share in a ring of `size`
/// entries (ForceField::share_ring_): the largest r such that the entries of any r + 1 consecutive
/// owners fill at most half the ring, and no larger than any entry's reach; 0 (no share in the
/// ring) if one owner's entries fill more. A share is read once the completion front passes its
/// partner, so the shares the ring must hold at once are those of the owners within r of the front,
/// plus a chunk of entries: half a ring leaves room for the batch's lag (pass_with's guard).
std::uint32_t ring_reach(const NeighborList& nl, std::size_t size) {
  const std::vector<std::uint32_t>& start = nl.starts();
  const std::size_t n = start.size() - 1, budget = size / 2;
  std::size_t reach = n;
  for (std::size_t i = 0, e = 0; i < n; ++i) {
    e = std::max(e, i);
    while (e < n && start[e + 1] - start[i] <= budget) ++e;  // owners [i, e) fit, [i, e] do not
    if (e == n) break;                                         // (nor does any window further on)
    if (e == i) return 0;
    reach = std::min(reach, e - i - 1);
  }
  std::uint32_t widest = 0;
  const std::vector<std::uint32_t>& owner = nl.owners();
  const std::vector<std::uint32_t>& partner = nl.partners();
  for (std::size_t k = 0; k < partner.size(); ++k) widest = std::max(widest, partner[k] - owner[k]);
  return static_cast<std::uint32_t>(std::min<std::size_t>(reach, widest));
}

/// Contact and rolling parameters for every material pair that is defined.
template <class Rolling, class MakeRolling>
ContactModels<Rolling> fill_models(const MaterialTable& mt, MakeRolling make_rolling) {
  const int n = mt.size();
  ContactModels<Rolling> m{n, std::vector<HertzMindlin::Params>(n * n), std::vector<typename Rolling::Params>(n * n)};
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      if (!mt.has_pair(a, b)) continue;  // never used: Simulation::setup checks pairs in use
      m.contact[a * n + b] = HertzMindlin::make(mt[a], mt[b], mt.pair(a, b));
      m.rolling[a * n + b] = make_rolling(mt.pair(a, b));
    }
  return m;
}

/// The history a new contact on `feature` of wall `wall` starts with: that of a contact this particle
/// had last step on an adjacent feature of the same wall that is no longer touched (a sphere rolling
/// across a mesh edge keeps its tangential spring: no force jump), else none.
ContactHistory inherited_history(const WallGeometry& g, const WallSlot* old, std::size_t stride, int previous,
                                 const WallHit* now, int found, std::int32_t wall, std::int32_t feature) {
  for (int o = 0; o < previous; ++o) {
    const WallSlot& s = old[o * stride];
    if (s.wall != wall || !g.continues(s.feature, feature)) continue;
    bool still_touched = false;
    for (int q = 0; q < found; ++q) still_touched |= now[q].feature == s.feature;
    if (!still_touched) return s.history;
  }
  return {};
}

}  // namespace

void ForceField::setup(const MaterialTable& mt, const std::vector<Wall>& walls, const RollingSettings& rs) {
  auto assign = [&](auto tag, auto make_rolling) {
    models_ = fill_models<decltype(tag)>(mt, make_rolling);
  };
  switch (rs.model) {
    case RollingModel::none:
      assign(NoRolling{}, [](const PairProperties& p) { return NoRolling::make(p); });
      break;
    case RollingModel::constant_torque:
      assign(ConstantTorqueRolling{}, [](const PairProperties& p) { return ConstantTorqueRolling::make(p); });
      break;
    case RollingModel::epsd:
      assign(EpsdRolling{}, [&](const PairProperties& p) {
        return EpsdRolling::make(p, rs.epsd_stiffness_factor, rs.epsd_damping_ratio);
      });
      break;
  }
  wall_material_.clear();
  for (const Wall& w : walls) wall_material_.push_back(w.material());
  list_generation_ = ~std::uint64_t{0};  // the contact flags are made again under the new models
}

ForceDiagnostics ForceField::compute(Particles& p, NeighborList& nl, const std::vector<Wall>& walls, double dt,
                                     AfterForces* after) {
  const int team = p.size() >= parallel_min_items() ? omp_get_max_threads() : 1;
  begin(p, nl, walls, team);
#pragma omp parallel if(team > 1) num_threads(team)
  pass(omp_get_num_threads(), omp_get_thread_num(), p, nl, walls, dt, after);
  return finish(dt);
}

void ForceField::begin(Particles& p, NeighborList& nl, const std::vector<Wall>& walls, int team) {
  std::visit([&](const auto& m) { begin_with(m, p, nl, walls, team); }, models_);
}

void ForceField::pass(int threads, int thread, Particles& p, NeighborList& nl, const std::vector<Wall>& walls, double dt,
                      AfterForces* after) {
  std::visit([&](const auto& m) { pass_with(m, threads, thread, p, nl, walls, dt, after); }, models_);
}

bool ForceField::begins_in_team(const Particles& p, const NeighborList& nl, const std::vector<Wall>& walls,
                                int team) const {
  // What begin() finds ready when it neither allocates nor runs a loop of its own (parallel or long):
  // a compute since the last list build (the flags, the masks, the block costs made), walls not moved
  // beyond their masks' margins, and room for the team.
  const std::size_t n = p.size(), entries = nl.entries();
  return list_generation_ == nl.generation() && touching_.size() == entries && partner_share_.size() == entries &&
         wall_slots_.stride() == n && block_cost_.size() == (n + kPassBlock - 1) / kPassBlock &&
         pass_stats_.size() >= static_cast<std::size_t>(team) && signals_.size() >= team && walls_where_found(walls, nl.frame()) &&
         ring_chosen(nl, n, team);
}

namespace {
/// The rings' size for a bed of n spheres: share_ring_entries() beyond the caches, else none.
std::size_t ring_size_for(std::size_t n) { return n >= beyond_cache_spheres() ? share_ring_entries() : 0; }
}  // namespace

bool ForceField::ring_chosen(const NeighborList& nl, std::size_t n, int team) const {
  const std::size_t size = ring_size_for(n);
  return ring_entries_ == size &&
         (size == 0 || (ring_generation_ == nl.generation() && share_ring_.size() >= static_cast<std::size_t>(team) * size));
}

void ForceField::choose_ring(const NeighborList& nl, std::size_t n, int team) {
  const std::size_t size = ring_size_for(n);
  assert(size == 0 || (size >= 2 * kEntryChunk && (size & (size - 1)) == 0));
  if (size == 0) {
    ring_entries_ = 0;
    return;
  }
  if (ring_entries_ != size || ring_generation_ != nl.generation()) {
    ring_reach_ = ring_reach(nl, size);
    ring_entries_ = size;
    ring_generation_ = nl.generation();
  }
  if (share_ring_.size() < static_cast<std::size_t>(team) * size) share_ring_.resize(static_cast<std::size_t>(team) * size);
}

/// Sphere i's wall contacts, queued in the batch; histories found by (wall, feature) among last
/// step's contacts of this particle.
template <class Rolling>
[[gnu::noinline]] void ForceField::add_wall_contacts(const Models<Rolling>& m, Particles& p,
                                                     const std::vector<Wall>& walls, std::size_t i, double dt,
                                                     WallBatch<Rolling>& batch, WallStats& ws, std::int64_t& bad) {
  const int previous = wall_slots_.before_counts()[i];
  const std::uint32_t near = near_walls_[i];
  const std::size_t stride = wall_slots_.stride();
  WallSlot* slots = wall_slots_.now(i);  // slot s at slots[s * stride]
  const WallSlot* old = wall_slots_.before(i);
  int used = 0;
  const Vec3 xi = p.x[i];
  // (Not loaded at all where the body gives them: a sphere's own v and omega were then stale lines,
  // two misses in three of this function's samples that were, perf, twenty-eighth session.)
  Vec3 vi, wi;
  if (body_motion_.x != nullptr) {
    const std::uint32_t k = p.body[i];
    wi = body_motion_.omega[k], vi = body_motion_.velocity_at(k, xi);
  } else {
    vi = p.v[i], wi = p.omega[i];
  }
  const double ri = p.radius[i], mass_i = p.mass[i], inertia_i = p.inertia[i];
  for (std::size_t w = 0; w < walls.size(); ++w) {
    if (w < kMaskedWalls && !(near >> w & 1u)) continue;  // out of reach until the masks are made again
    UninitializedArray<WallHit, kWallSlots + 1> hits;
    const int found = hint_index_[w] < 0 ? walls[w].hits(xi, ri, hits.data(), kWallSlots + 1)
                                         : walls[w].hits(xi, ri, hits.data(), kWallSlots + 1,
                                                         wall_hints_[i * hinted_walls_ + hint_index_[w]]);
    const WallPose& pose = walls[w].pose();
    const int pair = p.material[i] * m.materials + wall_material_[w];
    for (int q = 0; q < found; ++q) {
      if (used == kWallSlots) {
        ws.overflow = std::min<std::int64_t>(ws.overflow, static_cast<std::int64_t>(i));
        break;
      }
      if (batch.size == WallBatch<Rolling>::kCapacity) flush_walls(batch, dt, p, ws, bad);
      // The contact in registers (no WallContact array: copied through memory field by field,
      // then read back whole, it stalled on store forwarding, a fifth of the wall contacts of a bed
      // on its floor); the slot filled in place, its history matched with local keys (matching
      // against fields just stored stalled too: a third of pass 2 on that bed). Wall::contact's
      // fields as plain locals, not its struct: GCC built the struct on the stack, 8 bytes at a time,
      // and read its normal back 16 at a time, a store-forwarding stall on a quarter of this
      // function's samples (perf, the 10^5 bed).
      const WallHit& hit = hits[q];
      const Vec3 normal = pose.direction_to_world(hit.normal);
      const double overlap = ri - hit.distance;
      const Vec3 point = xi - hit.distance * normal;  // (as Wall::contact(hit, xi, ri) has them)
      const int feature = hit.feature;
      const std::int32_t wall = static_cast<std::int32_t>(w);
      WallSlot& s = slots[used++ * stride];
      s.wall = wall;
      s.feature = feature;
      int match = -1;
      for (int o = 0; o < previous; ++o) {
        if (old[o * stride].wall == wall && old[o * stride].feature == feature) match = o;
      }
      // The history goes into the batch from where it is now, not through the slot (flush_walls
      // writes the slot): read back in pieces right after a whole copy, it stalled on store
      // forwarding.
      const ContactHistory h =
          match >= 0 ? old[match * stride].history
                     : (previous > 0 ? inherited_history(walls[w].geometry(), old, stride, previous, hits.data(),
                                                         found, wall, feature)
                                     : ContactHistory{});
      const int b = batch.size++;
      const double lever = ri - overlap;  // as WallBatch::kinematics has it
      const Vec3 v_rel = vi - lever * cross(wi, normal) - pose.surface_velocity(point);
      batch.nx[b] = normal.x, batch.ny[b] = normal.y, batch.nz[b] = normal.z;
      batch.overlap[b] = overlap, batch.ri[b] = ri;
      batch.vx[b] = v_rel.x, batch.vy[b] = v_rel.y, batch.vz[b] = v_rel.z;
      batch.wix[b] = wi.x, batch.wiy[b] = wi.y, batch.wiz[b] = wi.z;
      batch.wjx[b] = pose.angular_velocity.x, batch.wjy[b] = pose.angular_velocity.y;
      batch.wjz[b] = pose.angular_velocity.z;
      batch.mi[b] = mass_i, batch.ii[b] = inertia_i;
      batch.contact[b] = m.contact[pair];
      batch.rolling[b] = m.rolling[pair];
      batch.sx[b] = h.shear.x, batch.sy[b] = h.shear.y, batch.sz[b] = h.shear.z;
      batch.rx[b] = h.rolling.x, batch.ry[b] = h.rolling.y, batch.rz[b] = h.rolling.z;
      batch.owner[b] = static_cast<std::uint32_t>(i);
      batch.slot[b] = &s;
    }
  }
  ws.contacts += static_cast<std::size_t>(used);
  wall_slots_.counts()[i] = static_cast<std::uint8_t>(used);
}

template <class Rolling>
void ForceField::flush_walls(WallBatch<Rolling>& b, double dt, Particles& p, WallStats& ws, std::int64_t& bad) {
  b.evaluate(dt);
  // Each contact's force and torque added to its sphere in the order found: the sums the
  // one-at-a-time loop took (its running sum started from the sphere's sums and partner shares).
  for (int c = 0; c < b.size; ++c) {
    const std::uint32_t i = b.owner[c];
    p.force[i] += Vec3{b.fx[c], b.fy[c], b.fz[c]};
    p.torque[i] += Vec3{b.tx[c], b.ty[c], b.tz[c]};
    b.slot[c]->history = {{b.sx[c], b.sy[c], b.sz[c]}, {b.rx[c], b.ry[c], b.rz[c]}};
    ws.worst_ratio = std::max(ws.worst_ratio, b.overlap_ratio[c]);
    ws.stiffness_per_mass = std::max(ws.stiffness_per_mass, b.stiffness_per_mass[c]);
    // A sphere's sum is complete at its last contact; a sum that is not finite before then is not
    // finite after (IEEE: nothing added to an infinity or a NaN makes it finite again).
    if (!is_finite(p.force[i]) || !is_finite(p.torque[i])) bad = std::min<std::int64_t>(bad, static_cast<std::int64_t>(i));
  }
  b.size = 0;
}

template <class Rolling>
void ForceField::flush_pairs(PairBatch<Rolling>& b, double dt, Particles& p, NeighborList& nl, OwnerSum& open,
                             double& worst_ratio, double& stiff_pair, PartnerShare* ring, std::uint32_t ring_mask) {
  b.evaluate(dt);
  // The open sums and the maxima in locals, the arrays as plain pointers. Through `open` every +=
  // went to memory (it may alias the arrays), and storing the complete sums read them back 16
  // bytes at a time over 8-byte stores: a failed store-to-load forward, which waits until every
  // older store has reached the cache (perf, the 10^5 bed, when the partner shares were stored
  // scattered, by reverse position: 62 % of this function's samples on that load). In-process A/B:
  // 10^5 bed +2.8 / +5.3 / +6.3 % (1 thread), the clump bed level (+1.3 / -1.0 %); the same numbers
  // bit for bit.
  std::size_t slot = open.slot;
  Vec3 sum_force = open.force, sum_torque = open.torque;
  double worst = worst_ratio, stiff = stiff_pair;
  const std::size_t n = p.size();
  Vec3 *const force = p.force.data(), *const torque = p.torque.data();
  Vec3 *const shear = nl.shear_data(), *const rolling = nl.rolling_data();
  PartnerShare* const share = partner_share_.data();
  const std::uint8_t* const touching = touching_.data();
  // In beds beyond the caches a sphere's sums are stored at each of its contacts, and started afresh
  // with a mask, not a branch: a branch on "a new owner?" followed no pattern there (a sphere owns 0
  // to 4 contacts) and was mispredicted, a third of this function's samples on the 10^5 bed (in
  // beds within the caches the predictor learns each step's pattern: the branch is cheaper there,
  // the clump bed 1.4 % slower without it). The last store is the complete sum, the same numbers.
  // Separate runs of one binary, the mask switched by the environment (seventeenth session, three
  // pairs each): the 2x platform box mid-rise +3.6 % on 1 thread, +4.2 % on 2; the 10^5 bed +1.6 %
  // and +0.5 %.
  auto contacts = [&]<bool kMasked>() {
    for (int c = 0; c < b.size; ++c) {
      const std::uint32_t i = b.owner[c];
      if constexpr (kMasked) {
        const std::uint64_t keep = -static_cast<std::uint64_t>(i == slot);  // all ones or none
        auto kept = [keep](double v) { return std::bit_cast<double>(std::bit_cast<std::uint64_t>(v) & keep); };
        sum_force = {kept(sum_force.x), kept(sum_force.y), kept(sum_force.z)};
        sum_torque = {kept(sum_torque.x), kept(sum_torque.y), kept(sum_torque.z)};
        slot = i;
        sum_force += Vec3{b.fx[c], b.fy[c], b.fz[c]};
        sum_torque += Vec3{b.tix[c], b.tiy[c], b.tiz[c]};
        force[i] = sum_force, torque[i] = sum_torque;
      } else {
        if (i != slot) {  // the open sphere has no more contacts: its sums are complete
          if (slot < n) force[slot] = sum_force, torque[slot] = sum_torque;
          slot = i, sum_force = {}, sum_torque = {};
        }
        sum_force += Vec3{b.fx[c], b.fy[c], b.fz[c]};
        sum_torque += Vec3{b.tix[c], b.tiy[c], b.tiz[c]};
      }
      const std::uint32_t k = b.entry[c];
      PartnerShare* const to = (touching[k] & kInRing) ? ring + (k & ring_mask) : share + k;
      *to = {{b.fx[c], b.fy[c], b.fz[c]}, {b.tjx[c], b.tjy[c], b.tjz[c]}};
      shear[k] = {b.sx[c], b.sy[c], b.sz[c]};
      if constexpr (Rolling::kSpring) rolling[k] = {b.rx[c], b.ry[c], b.rz[c]};
      worst = std::max(worst, b.overlap_ratio[c]);
      stiff = std::max(stiff, b.stiffness_per_mass[c]);
    }
  };
  if (n >= beyond_cache_spheres()) {
    contacts.template operator()<true>();
  } else {
    contacts.template operator()<false>();
  }
  open = {slot, sum_force, sum_torque};
  worst_ratio = worst, stiff_pair = stiff;
  b.size = 0;
}

template <class Rolling>
void ForceField::begin_with(const Models<Rolling>& /*the rolling model's type only*/, Particles& p, NeighborList& nl,
                            const std::vector<Wall>& walls, int team) {
  const std::size_t n = p.size();
  const std::size_t entries = nl.entries();
  partner_share_.resize(entries);
  // Wall contacts are double-buffered: last step's are read from the scratch buffer while this
  // step's are written (no copy of a sphere's old slots, which perf showed stalling on the stores
  // it had just made). Both sized for spheres added since.
  resize(n);
  wall_slots_.flip();
  // Only a model with a rolling spring keeps one per entry (a model without drops any left, as a
  // checkpoint of an EPSD run restarted under another model has: it neither reads nor writes them).
  nl.keep_rolling_springs(Rolling::kSpring);
  if (list_generation_ != nl.generation() || touching_.size() != entries) {
    // A new list: flag every entry whose carried-over history is non-zero (then cleared if apart).
    touching_.resize(entries);
    for (std::uint32_t k = 0; k < entries; ++k) {
      touching_[k] = norm2(nl.shear(k)) != 0 || (Rolling::kSpring && norm2(nl.rolling(k)) != 0);
    }
    list_generation_ = nl.generation();
    find_near_walls(p, walls, nl, true);
    split_stale_ = true;
  } else if (!walls_where_found(walls, nl.frame())) {
    find_near_walls(p, walls, nl, false);
    split_stale_ = true;
  }
  const std::size_t blocks = (n + kPassBlock - 1) / kPassBlock;
  split_stale_ |= block_cost_.size() != blocks;  // (spheres are only added with a new list: belt and braces)
  if (split_stale_) {  // each block's estimated cost: its spheres, the entries they own, those near a wall
    block_cost_.resize(blocks);
    const std::uint32_t* const first = nl.starts().data();
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t lo = b * kPassBlock, hi = std::min(n, lo + kPassBlock);
      std::size_t near = 0;
      for (std::size_t i = lo; i < hi; ++i) near += wall_in_reach(i, walls.size());
      block_cost_[b] = kSphereCost * static_cast<double>(hi - lo) + kEntryCost * (first[hi] - first[lo]) +
                       kWallSphereCost * static_cast<double>(near);
    }
  }
  if (split_stale_ || work_split_.threads() != team || work_split_.rebalance()) {
    work_split_.split(block_cost_, team);
    split_stale_ = false;
  }
  choose_ring(nl, n, team);
  signals_.reserve(team);
  if (pass_stats_.size() < static_cast<std::size_t>(team)) pass_stats_.resize(team);
  pairs_done_ = signals_.next_epoch(), forces_done_ = signals_.next_epoch();
}

template <class Rolling>
void ForceField::pass_with(const Models<Rolling>& m, int threads, int thread, Particles& p, NeighborList& nl,
                           const std::vector<Wall>& walls, double dt, AfterForces* after) {
  assert(thread < threads && static_cast<std::size_t>(threads) <= pass_stats_.size());
  if (thread == 0) pass_team_ = threads;  // (a region may get fewer threads than begin() was told)
  const std::size_t n = p.size();
  const std::size_t entries = nl.entries();
  const std::uint64_t pairs_done = pairs_done_, forces_done = forces_done_;
  // This thread's part of the step's diagnostics (PassStats), combined by finish().
  std::size_t contacts = 0, wall_contacts = 0;
  double worst_ratio = 0, stiff_pair = 0;  // stiff_*: max S_n / m* (for the omega dt monitor)
  std::int64_t bad = std::numeric_limits<std::int64_t>::max();
  std::int64_t overflow = std::numeric_limits<std::int64_t>::max();
  double worst_wall = 0, stiff_wall = 0;

  // One sweep over the spheres, in blocks, with two fronts, in beds beyond the caches; beds within
  // them complete every block in a second loop (until 2026-12-05 every bed did: docs/performance.md).
  // - The pair front: every pair once, by its owner i (the smaller slot). The owner's share is
  //   summed in entry order and stored when complete; the partner's share is stored by entry. The
  //   entry loop only finds the touching pairs and gathers them into a batch per thread; a full
  //   batch is evaluated at once, vectorised (dem/pair_batch.hpp; the same numbers as one contact at
  //   a time). A sphere's sums stay open across a batch that ends inside its entries. The loop walks
  //   a block's entries, not its spheres: in a settled bed most spheres own no entry (the clump
  //   bed: 0.5 per sphere), and a sphere loop paid for each a mispredicted "any entries?" branch and
  //   the loads of its state. A block's forces and torques are zeroed first.
  // - The completion front, right behind it: each time a batch has been evaluated, every sphere
  //   before the owner of its last contact has all its pairs evaluated (its own, and those of
  //   owners before it, since a pair's owner is its smaller slot), so its force is completed: the
  //   partner shares added in reverse-range order, then its wall contacts. What that reads (the
  //   sphere's state, its sums, the shares) was touched a batch or a few hundred spheres ago and is
  //   still in the caches; a second pass over a bed beyond the caches read it all from memory again
  //   (in-process A/B: 10^5 bed +4.5 / +9.0 % on 1 thread, +6.6 / +3.6 % on 2; the poured 2x platform
  //   box +10 / +17.5 % and +15.6 / +10.3 %). In beds within the caches the interleaving only cost
  //   (the clump bed, 10^4 and 10^3: 0 to -3 %), hence the second loop there.
  // Every sphere's force is the same sum in the same order for any thread count: its own contacts in
  // entry order, the partner shares in reverse-range order, its wall contacts in the order found.
  // Each thread takes one range of blocks, the same from step to step until the split is made again
  // (dem/work_split.hpp: ranges of about equal time, so that a sphere's state stays on one core). A
  // thread cannot complete its first spheres whose pairs have owners before its range (slots [range
  // start, NeighborList::reach_before(range start))): they are completed once the threads below have
  // evaluated their pairs.
  {
    // Plain local pointers, declared inside the parallel region, and copied into `complete` (not
    // inlined), whose by-reference captures would make them escape: a one-byte store (the contact
    // flags) may alias anything, and GCC reloaded every array's address from memory after each one.
    // Declared outside the region they were shared variables, reached through the region's argument
    // block: two dependent loads before each partner's position (perf: the clump bed's hottest
    // instruction, 9 % of the step, was the load of x[j] behind them). In the region: the same
    // numbers, the clump bed -2 to -22 % time on 1 thread (6 interleaved pairs; docs/performance.md).
    const Vec3 *const x = p.x.data(), *const v = p.v.data(), *const omega = p.omega.data();
    // A sphere's velocity and angular velocity (at x_s): its own, or from its body's
    // (read_motion_from_bodies).
    const BodyMotion body = body_motion_;
    const bool by_body = body.x != nullptr;
    const std::uint32_t* const body_of = p.body.data();
    auto motion = [&](std::uint32_t s, const Vec3& xs, Vec3& vs, Vec3& ws) __attribute__((always_inline)) {
      if (!by_body) {
        vs = v[s], ws = omega[s];
        return;
      }
      const std::uint32_t k = body_of[s];
      ws = body.omega[k], vs = body.velocity_at(k, xs);
    };
    const double *const radius = p.radius.data(), *const mass = p.mass.data(), *const inertia = p.inertia.data();
    const std::int32_t* const material = p.material.data();
    const std::uint32_t *const start = nl.starts().data(), *const partner = nl.partners().data();
    const std::uint32_t* const owner = nl.owners().data();
    const std::uint32_t *const rev_start = nl.rev_starts().data(), *const rev_owner = nl.rev_owners().data();
    const std::uint32_t* const rev_entry = nl.rev_entries().data();
    Vec3 *const shear = nl.shear_data(), *const rolling = nl.rolling_data();
    std::uint8_t* const touching = touching_.data();
    Vec3 *const force = p.force.data(), *const torque = p.torque.data();
    const PartnerShare* const share = partner_share_.data();
    const std::uint8_t* const before_count = wall_slots_.before_counts();
    std::uint8_t* const count = wall_slots_.counts();
    const HertzMindlin::Params* const contact_params = m.contact.data();
    const typename Rolling::Params* const rolling_params = m.rolling.data();
    const int materials = m.materials;
    const bool beyond_cache = n >= beyond_cache_spheres();
    const bool fused = beyond_cache;  // else the completion is a second loop over the blocks
    const std::size_t blocks_ahead = beyond_cache ? prefetch_blocks(n, entries, Rolling::kSpring) : 0;
    // Entry k (owner i, partner j, d = x_i - x_j) touches: its pair goes into the batch's slot b.
    auto gather = [&](PairBatch<Rolling>& batch, int b, std::uint32_t k, std::uint32_t i, std::uint32_t j, Vec3 d,
                      double dist2, double rsum, double ri, Vec3 vi, Vec3 wi, double mass_i, double inertia_i, int row) {
      batch.dx[b] = d.x, batch.dy[b] = d.y, batch.dz[b] = d.z;
      batch.dist2[b] = dist2, batch.rsum[b] = rsum, batch.ri[b] = ri, batch.rj[b] = radius[j];
      Vec3 vj, wj;
      motion(j, x[j], vj, wj);
      const Vec3 dv = vi - vj;
      batch.dvx[b] = dv.x, batch.dvy[b] = dv.y, batch.dvz[b] = dv.z;
      batch.wix[b] = wi.x, batch.wiy[b] = wi.y, batch.wiz[b] = wi.z;
      batch.wjx[b] = wj.x, batch.wjy[b] = wj.y, batch.wjz[b] = wj.z;
      batch.mi[b] = mass_i, batch.mj[b] = mass[j], batch.ii[b] = inertia_i, batch.ij[b] = inertia[j];
      const int pair = row + material[j];
      batch.contact[b] = contact_params[pair];
      batch.rolling[b] = rolling_params[pair];
      const Vec3 s = shear[k];
      batch.sx[b] = s.x, batch.sy[b] = s.y, batch.sz[b] = s.z;
      if constexpr (Rolling::kSpring) {
        const Vec3 rs = rolling[k];
        batch.rx[b] = rs.x, batch.ry[b] = rs.y, batch.rz[b] = rs.z;
      }
      batch.owner[b] = i, batch.entry[b] = k;
    };
    // The partner of the entry kPrefetchEntries ahead, in beds too large for the caches. (Both
    // prefetching lambdas always inlined, so that tests/dem/prefetches_kept.sh finds their
    // prefetches in the pass itself.)
    auto prefetch_ahead = [&](std::uint32_t k) __attribute__((always_inline)) {
      if (k + kPrefetchEntries >= entries) return;
      const std::uint32_t ahead = partner[k + kPrefetchEntries];
      prefetch_for_read(&x[ahead]), prefetch_for_read(&radius[ahead]);
      if (by_body) {
        prefetch_for_read(&body_of[ahead]);
      } else {
        prefetch_for_read(&v[ahead]), prefetch_for_read(&omega[ahead]);
      }
      prefetch_for_read(&mass[ahead]), prefetch_for_read(&inertia[ahead]), prefetch_for_read(&material[ahead]);
    };
    const WallGeometry::Hint* const hints = hinted_walls_ > 0 ? wall_hints_.data() : nullptr;
    // The lines block `ahead` will walk in order, in beds too large for the caches (prefetch_blocks),
    // into the second-level cache, those to be written too (dem/prefetch.hpp). Until 2026-12-07
    // they went to the first level, the written ones requested for writing (prefetchw). Separate
    // runs of one binary, the kind switched by the environment (twenty-first session, rounds of
    // both): the 10^5 bed +2.5 to +12.6 % on 1 thread (eleven rounds), +2.8 to +10 % per CPU on 2;
    // the platform box mid-rise +6 to +10 % on 1, +1.7 to +16 % on 2 (docs/performance.md).
    // Inlined as the A/Bs measured it (GCC 12 put it out of line once it requested the row starts).
    auto prefetch_block = [&](std::size_t ahead) __attribute__((always_inline)) {
      const std::size_t lo = ahead * kPassBlock, hi = std::min(n, lo + kPassBlock);
      prefetch_lines_to_l2(x + lo, x + hi);
      if (by_body) {
        prefetch_lines_to_l2(body_of + lo, body_of + hi);
      } else {
        prefetch_lines_to_l2(v + lo, v + hi), prefetch_lines_to_l2(omega + lo, omega + hi);
      }
      prefetch_lines_to_l2(radius + lo, radius + hi), prefetch_lines_to_l2(mass + lo, mass + hi);
      prefetch_lines_to_l2(inertia + lo, inertia + hi), prefetch_lines_to_l2(material + lo, material + hi);
      prefetch_lines_to_l2(force + lo, force + hi), prefetch_lines_to_l2(torque + lo, torque + hi);
      prefetch_lines_to_l2(before_count + lo, before_count + hi), prefetch_lines_to_l2(count + lo, count + hi);
      // The row starts, of which it reads the block's two ends here, were requested one distance
      // earlier, with those of the block one distance farther now: loaded here at full latency, the
      // two ends had 8 % of the pass's samples in the platform box (in-process A/B, sixteenth
      // session: +1.1 to +3.6 % there mid-rise on 1 thread, +1.7 / +1.8 % on 2; the 10^5 bed level).
      // The ring's guard and `complete` read both arrays at any sphere the fronts have passed.
      if (const std::size_t lo2 = lo + blocks_ahead * kPassBlock; lo2 < n) {
        const std::size_t hi2 = std::min(n, lo2 + kPassBlock);
        prefetch_lines_to_l2(start + lo2, start + hi2 + 1);
        prefetch_lines_to_l2(rev_start + lo2, rev_start + hi2 + 1);
      }
      const std::uint32_t e0 = start[lo], e1 = start[hi];
      prefetch_lines_to_l2(owner + e0, owner + e1), prefetch_lines_to_l2(partner + e0, partner + e1);
      prefetch_lines_to_l2(touching + e0, touching + e1), prefetch_lines_to_l2(shear + e0, shear + e1);
      if constexpr (Rolling::kSpring) prefetch_lines_to_l2(rolling + e0, rolling + e1);
      const std::uint32_t r0 = rev_start[lo], r1 = rev_start[hi];
      prefetch_lines_to_l2(rev_entry + r0, rev_entry + r1);
      prefetch_lines_to_l2(rev_owner + r0, rev_owner + r1);
    };
    PairBatch<Rolling> batch;
    OwnerSum open{n};
    WallStats ws;
    WallBatch<Rolling> wall_batch;
    // This thread's blocks [mine, mine_end), spheres [first, end).
    const bool as_split = threads == work_split_.threads();
    std::size_t mine = 0, mine_end = 0;
    thread_blocks(n, threads, thread, mine, mine_end);
    const std::size_t first = std::min(n, mine * kPassBlock), end = std::min(n, mine_end * kPassBlock);
    // Spheres before `done` are completed, or left for after the threads below: [first, deferred).
    const std::size_t deferred = first < end ? std::min<std::size_t>(end, nl.reach_before(first)) : first;
    std::size_t done = std::max(first, deferred);
    // This thread's ring of partner shares (share_ring_), for the spheres its completion front
    // completes, [deferred, end), whose pairs reach no further than ring_reach; the other shares go
    // to partner_share_. A touching entry's flag says where its share is (kInRing).
    const std::size_t ring_size = fused && ring_reach_ > 0 ? ring_entries_ : 0;  // (reach 0: no share fits)
    PartnerShare* const ring = ring_size > 0 ? share_ring_.data() + static_cast<std::size_t>(thread) * ring_size : nullptr;
    const std::uint32_t ring_mask = ring_size > 0 ? static_cast<std::uint32_t>(ring_size - 1) : 0;
    const std::uint32_t ring_reach = ring_size > 0 ? ring_reach_ : 0;  // 0: no pair (partner > owner)
    const std::uint32_t ring_lo = static_cast<std::uint32_t>(deferred);
    const std::uint32_t ring_span = static_cast<std::uint32_t>(end - deferred);
    // Spheres [from, to) completed: the partner shares (walked by reverse position as the pair front
    // walks entries: most spheres of a settled bed have none, so no per-sphere branch on it; a share
    // is current if its entry is touching, and in the ring if flagged kInRing), then the wall contacts, a function of their own, not
    // inlined: most spheres skip them, and inlined they left too few registers for the loop.
    // Whether sphere i's wall contacts must be looked for: most of a bed has no wall within reach
    // and had no wall contact.
    auto near_a_wall = [&](std::size_t i) {  // (no branch in it: the wall list counts with it)
      return (before_count[i] > 0) | wall_in_reach(i, walls.size());
    };
    auto complete = [&, rev_start, rev_entry, rev_owner, touching, force, torque, share, ring, ring_mask, count](
                        std::size_t from, std::size_t to) {
      for (std::uint32_t r = rev_start[from], last = rev_start[to]; r < last; ++r) {
        const std::uint32_t k = rev_entry[r];
        const std::uint8_t flag = touching[k];
        if (!flag) continue;
        const std::uint32_t i = rev_owner[r];
        const PartnerShare& got = (flag & kInRing) ? ring[k & ring_mask] : share[k];
        force[i] -= got.force;
        torque[i] += got.torque;
      }
      // x * 0 is 0 for a finite x and NaN for an infinity or a NaN: one test for all six (no branch
      // per component on every sphere).
      auto check = [&](std::size_t i) {
        const Vec3 f = force[i], t = torque[i];
        const double probe = (f.x * 0 + f.y * 0 + f.z * 0) + (t.x * 0 + t.y * 0 + t.z * 0);
        if (probe != 0) bad = std::min<std::int64_t>(bad, static_cast<std::int64_t>(i));
      };
      // Beds beyond the caches: the spheres near a wall listed without a branch, a block at a time,
      // then their wall contacts. A branch per sphere on "near a wall?" followed no pattern the
      // predictor could learn there (a third of the scaling beds' spheres lie on the floor; in beds
      // within the caches it learns each step's pattern, and the list cost 0.6-0.7 %: the 10^3 bed,
      // the clump bed). The same contacts in the same order, each sphere checked once its sums are
      // whole (a sum not finite before its wall contacts are added is not finite after). Separate
      // runs of one binary, the list switched by the environment (seventeenth session, three
      // pairs): the 2x platform box mid-rise +9.6 % on 1 thread, +0.5 % on 2; the 10^5 bed +3.9 %
      // and +2.5 %.
      if (fused) {
        for (std::size_t c0 = from; c0 < to; c0 += kPassBlock) {
          const std::size_t c1 = std::min(to, c0 + kPassBlock);
          std::uint32_t walled[kPassBlock];
          int found_walled = 0;
          for (std::size_t i = c0; i < c1; ++i) {
            const std::uint32_t w = near_a_wall(i);
            walled[found_walled] = static_cast<std::uint32_t>(i);
            found_walled += static_cast<int>(w);
            count[i] = static_cast<std::uint8_t>(count[i] & (0u - w));
            check(i);
          }
          for (int q = 0; q < found_walled; ++q) {
            const std::uint32_t i = walled[q];
            add_wall_contacts(m, p, walls, i, dt, wall_batch, ws, bad);
          }
        }
        return;
      }
      for (std::size_t i = from; i < to; ++i) {
        if (near_a_wall(i)) {
          const int queued = wall_batch.size;
          add_wall_contacts(m, p, walls, i, dt, wall_batch, ws, bad);
          if (count[i] > 0 || wall_batch.size != queued) continue;  // checked when its contacts are added
        } else {
          count[i] = 0;
        }
        check(i);
      }
    };
    // A full batch evaluated: the spheres before the owner of its last contact are complete. Their
    // wall slots, the one thing of theirs the pair front has not touched, are fetched first, to
    // arrive while the batch is evaluated: the whole of the first slot, whose 56 bytes straddle two
    // lines for 6 spheres in 8 (its first line alone left the history's load a miss, 60 % of
    // add_wall_contacts' samples in the tilting platform box; in-process A/B +4.9 %); and their
    // wall hints (mesh walls: the record of the sphere's cell, else a load scattered over the
    // mesh's grid, a third of MeshGeometry's time; hints and prefetch, in-process A/B on the tilting
    // platform box: +3.8 % on 1 thread, +1.9 % on 2; without the prefetch the miss moved to the hint).
    auto flush = [&](int b) {
      batch.size = b;
      if (fused) {
        const std::size_t to = batch.owner[b - 1];
        for (std::size_t i = done; i < to; ++i) {
          if (near_a_wall(i)) {
            prefetch_lines(wall_slots_.before(i), wall_slots_.before(i) + 1);
            prefetch_lines(wall_slots_.now(i), wall_slots_.now(i) + 1, true);
            if (hints != nullptr) prefetch_lines(hints + i * hinted_walls_, hints + (i + 1) * hinted_walls_);
          }
        }
      }
      flush_pairs(batch, dt, p, nl, open, worst_ratio, stiff_pair, ring, ring_mask);
      if (fused && open.slot < n && open.slot > done) complete(done, open.slot), done = open.slot;
    };
    AfterForces::Progress progress;  // the follow-up's, between its calls (AfterForces)
    const bool ready_calls = fused && after != nullptr && after->wants_ready();
    const std::size_t ready_from = done;
    std::size_t ready_to = done;
    double busy = -omp_get_wtime();  // this thread's seconds in its blocks, for the next split
    for (std::size_t block = mine; block < mine_end; ++block) {
      const std::size_t lo = block * kPassBlock, hi = std::min(n, lo + kPassBlock);
      if (beyond_cache && block + blocks_ahead < mine_end) prefetch_block(block + blocks_ahead);
      for (std::size_t i = lo; i < hi; ++i) force[i] = {}, torque[i] = {};
      int b = batch.size;  // in a register, stored back before a flush
      if (!beyond_cache) {
        // Entry by entry, the owner's state loaded when the owner changes.
        std::uint32_t i = ~0u;
        Vec3 xi, vi, wi;
        double ri = 0, mass_i = 0, inertia_i = 0;
        int row = 0;
        for (std::uint32_t k = start[lo], last = start[hi]; k < last; ++k) {
          if (owner[k] != i) {
            i = owner[k];
            xi = x[i];
            motion(i, xi, vi, wi);
            ri = radius[i], mass_i = mass[i], inertia_i = inertia[i];
            row = material[i] * materials;
          }
          const std::uint32_t j = partner[k];
          const Vec3 d = xi - x[j];
          const double rsum = ri + radius[j];
          const double dist2 = norm2(d);
          if (dist2 >= rsum * rsum) {
            if (touching[k]) {  // contact broken: history starts afresh next time
              shear[k] = {};
              if constexpr (Rolling::kSpring) rolling[k] = {};
              touching[k] = 0;
            }
            continue;
          }
          touching[k] = 1;
          ++contacts;
          gather(batch, b, k, i, j, d, dist2, rsum, ri, vi, wi, mass_i, inertia_i, row);
          if (++b == PairBatch<Rolling>::kCapacity) flush(b), b = 0;
        }
      } else {
        // A bed beyond the caches: first the distance tests of a chunk of entries, with no branch
        // per entry (the flags set as found, the touching entries listed), then the touching ones
        // gathered, each with its owner's state. The same pairs in the same order as the loop
        // above, so the same numbers; but there a branch on "touching?" or "new owner?" waits on a
        // miss, and when mispredicted (a quarter of the 10^5 bed's entries are apart) throws away
        // the loads issued after it. In-process A/B (two copies of the settled bed, 25-step blocks
        // alternated, both orders): 10^5 bed +4.6 % on 1 thread, +5.2 % on 2; the poured 2x
        // platform box (84,109 spheres) +3.7 % and +3.1 %; the 10^4 bed +4 %, but the clump bed
        // -3 % (its contacts are mostly an owner's only entry), hence two loops.
        std::uint32_t listed[kEntryChunk];
        for (std::uint32_t chunk = start[lo], last = start[hi]; chunk < last; chunk += kEntryChunk) {
          const std::uint32_t chunk_end = std::min(last, chunk + kEntryChunk);
          if (ring != nullptr) {
            // The ring's guard. A share in the ring not read yet has its partner at or after `done`,
            // so its owner at or after done - ring_reach, and its entry at or after `oldest`: the
            // shares of this chunk may take their slots only if they lie within a ring of it. Else
            // the batch is evaluated now and the spheres before this chunk's first owner completed
            // (all their pairs are in): ring_reach_ keeps that owner's window within half a ring.
            const std::size_t oldest = start[done >= first + ring_reach ? done - ring_reach : first];
            if (chunk_end > oldest + ring_size) {
              if (b > 0) flush(b), b = 0;
              const std::size_t upto = owner[chunk];
              if (open.slot < upto) {  // its entries are all in: its sums are complete
                force[open.slot] = open.force, torque[open.slot] = open.torque;
                open = {n, {}, {}};
              }
              if (upto > done) complete(done, upto), done = upto;
              assert(chunk_end <= start[done >= first + ring_reach ? done - ring_reach : first] + ring_size);
            }
          }
          std::uint32_t found = 0;
          std::uint8_t broken = 0;
          for (std::uint32_t k = chunk; k < chunk_end; ++k) {
            prefetch_ahead(k);
            const std::uint32_t i = owner[k], j = partner[k];
            const Vec3 d = x[i] - x[j];
            const double rsum = radius[i] + radius[j];
            const std::uint8_t now = norm2(d) < rsum * rsum;
            const std::uint8_t in_ring = (j - ring_lo < ring_span) & (j - i <= ring_reach);
            listed[found] = k;
            found += now;
            broken |= touching[k] & (now ^ 1);
            touching[k] = now | static_cast<std::uint8_t>((now & in_ring) << 1);
          }
          if (broken) {  // contacts broken: histories start afresh (an entry apart holds none)
            for (std::uint32_t k = chunk; k < chunk_end; ++k) {
              if (touching[k]) continue;
              shear[k] = {};
              if constexpr (Rolling::kSpring) rolling[k] = {};
            }
          }
          contacts += found;
          for (std::uint32_t q = 0; q < found; ++q) {
            const std::uint32_t k = listed[q], i = owner[k], j = partner[k];
            const Vec3 d = x[i] - x[j];
            Vec3 vi, wi;
            motion(i, x[i], vi, wi);
            gather(batch, b, k, i, j, d, norm2(d), radius[i] + radius[j], radius[i], vi, wi, mass[i],
                   inertia[i], material[i] * materials);
            if (++b == PairBatch<Rolling>::kCapacity) flush(b), b = 0;
          }
        }
      }
      batch.size = b;
      if (ready_calls) {
        // Final: the completed spheres, but for those whose wall contacts wait in the wall batch.
        const std::size_t final_to = wall_batch.size > 0 ? std::min<std::size_t>(done, wall_batch.owner[0]) : done;
        if (final_to > ready_to) after->ready(threads, thread, ready_from, final_to, progress), ready_to = final_to;
      }
    }
    flush_pairs(batch, dt, p, nl, open, worst_ratio, stiff_pair, ring, ring_mask);
    if (open.slot < n) force[open.slot] = open.force, torque[open.slot] = open.torque;
    if (fused && end > done) complete(done, end);
    // The spheres' shares of the pairs this thread owns are stored: the threads above may complete
    // their first spheres (dem/team_signals.hpp). This thread waits only for those below: a sphere's
    // shares come from pairs owned by smaller slots.
    signals_.post(thread, pairs_done);
    busy += omp_get_wtime();
    for (int below = 0; below < thread; ++below) signals_.wait(below, pairs_done);
    busy -= omp_get_wtime();
    if (fused) {
      // The first spheres of the range, whose pairs with owners before it are all evaluated now.
      if (deferred > first) complete(first, deferred);
    } else {
      complete(first, end);
    }
    busy += omp_get_wtime();
    if (as_split) work_split_.report(thread, busy);
    flush_walls(wall_batch, dt, p, ws, bad);
    wall_contacts += ws.contacts;
    overflow = std::min(overflow, ws.overflow);
    worst_wall = std::max(worst_wall, ws.worst_ratio);
    stiff_wall = std::max(stiff_wall, ws.stiffness_per_mass);
    // This thread's spheres' forces are complete.
    signals_.post(thread, forces_done);
    pass_stats_[thread] = {contacts, wall_contacts, worst_ratio, stiff_pair, worst_wall, stiff_wall, bad, overflow};
    if (after != nullptr) after->run(ForceTeam(signals_, forces_done, threads, thread), progress);
  }
}

ForceDiagnostics ForceField::finish(double dt) {
  work_split_.step_done();
  // Sums of counts and extremes: the same whatever the order the threads are taken in.
  PassStats all{};
  for (int t = 0; t < pass_team_; ++t) {
    const PassStats& s = pass_stats_[t];
    all.contacts += s.contacts, all.wall_contacts += s.wall_contacts;
    all.worst_ratio = std::max(all.worst_ratio, s.worst_ratio), all.stiff_pair = std::max(all.stiff_pair, s.stiff_pair);
    all.worst_wall = std::max(all.worst_wall, s.worst_wall), all.stiff_wall = std::max(all.stiff_wall, s.stiff_wall);
    all.bad = std::min(all.bad, s.bad), all.overflow = std::min(all.overflow, s.overflow);
  }
  ForceDiagnostics d;
  d.contacts = all.contacts;
  d.wall_contacts = all.wall_contacts;
  d.max_overlap_ratio = std::max(all.worst_ratio, all.worst_wall);
  d.max_omega_dt = dt * std::sqrt(std::max(all.stiff_pair, all.stiff_wall));
  d.bad_slot = all.bad == std::numeric_limits<std::int64_t>::max() ? -1 : all.bad;
  d.slot_overflow = all.overflow == std::numeric_limits<std::int64_t>::max() ? -1 : all.overflow;
  return d;
}

void ForceField::find_near_walls(const Particles& p, const std::vector<Wall>& walls, const NeighborList& nl,
                                 bool at_build) {
  // Sphere i may touch wall w before the masks are made again only if, seen from the wall's frame,
  // it is now within r_i + reach of the wall, where reach covers
  //   - the sphere's own travel in the list's frame (dem/list_frame.hpp): at most skin/2 from where
  //     the list was built; so at most skin/2 from where it is now at a build, a whole skin between
  //     builds; plus half a skin for round-off;
  //   - the wall's travel in the list's frame: a wall that moves there (one with a motion, or any
  //     wall but the frame's own once the frame is a moving container's) gets kMovingWallMargin; the
  //     masks are made again once some point of the region the spheres occupy in the list's frame
  //     has moved that far in the wall's frame (walls_where_found). A wall at rest in the list's
  //     frame has margin 0: any new pose means new masks.
  // Every wall is asked for a stray with slack (it may move further than skin/2 before the next
  // build), and walls beyond the mask always.
  const double skin = nl.skin();
  const double travel = (at_build ? 1.0 : 1.5) * skin;
  const std::vector<double>& slack = nl.slack2();
  const ListFrame& frame = nl.frame();
  const WallPose frame_pose = frame.in_wall() ? walls[frame.wall].pose() : WallPose{};
  const std::size_t n = p.size();
  const std::size_t masked = std::min(walls.size(), kMaskedWalls);
  near_walls_.resize(n);
  mask_margin_.assign(masked, 0.0);
  for (std::size_t w = 0; w < masked; ++w) {
    if (moves_in_frame(walls[w], frame)) mask_margin_[w] = kMovingWallMargin * skin;
  }
  double lox = kInf, loy = kInf, loz = kInf, hix = -kInf, hiy = -kInf, hiz = -kInf;
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static) reduction(min : lox, loy, loz) \
    reduction(max : hix, hiy, hiz)
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t near = 0;
    if (i < slack.size() && slack[i] > 0) {
      near = ~0u;
    } else {
      const Vec3 y = frame.to_frame(frame_pose, p.x[i]);
      lox = std::min(lox, y.x), loy = std::min(loy, y.y), loz = std::min(loz, y.z);
      hix = std::max(hix, y.x), hiy = std::max(hiy, y.y), hiz = std::max(hiz, y.z);
    }
    for (std::size_t w = 0; w < masked; ++w) {
      if (near >> w & 1u) continue;
      WallContact wc[kWallSlots + 1];
      if (walls[w].contacts(p.x[i], p.radius[i] + travel + mask_margin_[w], wc, kWallSlots + 1) > 0) {
        near |= 1u << w;
      }
    }
    near_walls_[i] = near;
  }
  mask_region_lo_ = {lox, loy, loz}, mask_region_hi_ = {hix, hiy, hiz};
  hint_index_.assign(walls.size(), -1);
  hinted_walls_ = 0;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    if (walls[w].geometry().uses_hints()) hint_index_[w] = static_cast<int>(hinted_walls_++);
  }
  if (at_build || wall_hints_.size() != n * hinted_walls_) wall_hints_.assign(n * hinted_walls_, WallGeometry::kNoHint);
  mask_poses_.clear();
  for (const Wall& w : walls) mask_poses_.push_back(w.pose());
  mask_frame_wall_ = frame.wall;
}

bool ForceField::walls_where_found(const std::vector<Wall>& walls, const ListFrame& frame) const {
  // The masks hold while no point of the spheres' region (the box around their positions in the
  // list's frame when the masks were made) has moved further than the wall's margin in the wall's
  // frame. The distance |P^-1 G y - P0^-1 G0 y| between where a point y of the list's frame sits in
  // the wall's frame now (wall pose P, list frame G) and then (P0, G0) is convex in y (the
  // difference of two rigid maps is affine), so its largest value over the box is at a corner. (In
  // the world's frame G = G0 = 1; a wall fixed in the list's frame has P^-1 G = P0^-1 G0.) A wall
  // added, one that started or stopped moving, or a new frame needs new masks too.
  if (mask_poses_.size() != walls.size() || near_walls_.empty() || mask_frame_wall_ != frame.wall) return false;
  const std::size_t masked = std::min(walls.size(), kMaskedWalls);
  if (mask_region_lo_.x > mask_region_hi_.x) return true;  // no sphere outside the strays
  // The list frame's pose now and then: its wall's (unused in the world's frame).
  const WallPose frame_now = frame.in_wall() ? walls[frame.wall].pose() : WallPose{};
  const WallPose frame_then = frame.in_wall() ? mask_poses_[frame.wall] : WallPose{};
  // The region's corners in the world now and then, once for all walls.
  Vec3 corner_now[8], corner_then[8];
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 y{corner & 1 ? mask_region_hi_.x : mask_region_lo_.x, corner & 2 ? mask_region_hi_.y : mask_region_lo_.y,
                 corner & 4 ? mask_region_hi_.z : mask_region_lo_.z};
    corner_now[corner] = frame.to_world(frame_now, y), corner_then[corner] = frame.to_world(frame_then, y);
  }
  for (std::size_t w = 0; w < masked; ++w) {
    if ((mask_margin_[w] > 0) != moves_in_frame(walls[w], frame)) return false;
    const WallPose& now = walls[w].pose();
    const WallPose& then = mask_poses_[w];
    double shift2 = 0;
    for (int corner = 0; corner < 8; ++corner) {
      shift2 = std::max(shift2, norm2(now.to_body(corner_now[corner]) - then.to_body(corner_then[corner])));
    }
    if (!(shift2 <= mask_margin_[w] * mask_margin_[w])) return false;
  }
  return true;
}

void ForceField::thread_blocks(std::size_t n, int team, int t, std::size_t& first, std::size_t& last) const {
  const std::size_t blocks = (n + kPassBlock - 1) / kPassBlock;
  if (team == work_split_.threads() && work_split_.last(team - 1) == blocks) {
    first = work_split_.first(t), last = work_split_.last(t);
  } else {
    equal_share(blocks, team, t, first, last);
  }
}

void ForceField::thread_spheres(std::size_t n, int team, int t, std::size_t& first, std::size_t& last) const {
  thread_blocks(n, team, t, first, last);
  first = std::min(n, first * kPassBlock), last = std::min(n, last * kPassBlock);
}

void ForceField::resize(std::size_t n) { wall_slots_.resize(n); }

void ForceField::permute(const Renumbering& r) { wall_slots_.permute(r); }

void ForceField::restore_wall_contacts(const std::vector<std::uint8_t>& counts, const std::vector<WallSlot>& used,
                                       std::size_t walls) {
  std::size_t total = 0;
  for (std::uint8_t c : counts) {
    if (c > kWallSlots) {
      throw std::invalid_argument("wall contacts: a particle has " + std::to_string(c) + " (at most " +
                                  std::to_string(kWallSlots) + ")");
    }
    total += c;
  }
  if (total != used.size()) {
    throw std::invalid_argument("wall contacts: the counts add up to " + std::to_string(total) + " but " +
                                std::to_string(used.size()) + " are stored");
  }
  for (const WallSlot& s : used) {
    if (s.wall < 0 || static_cast<std::size_t>(s.wall) >= walls) {
      throw std::invalid_argument("wall contacts: wall index " + std::to_string(s.wall) + " outside [0, " +
                                  std::to_string(walls) + ")");
    }
  }
  wall_slots_.assign(counts, used);  // may be fewer than the particles: resize() extends
}

ContactEnergy ForceField::contact_energy(const Particles& p, const NeighborList& nl,
                                         const std::vector<Wall>& walls) const {
  ContactEnergy e;
  const int nm = std::visit([](const auto& m) { return m.materials; }, models_);
  const auto& contact = std::visit([](const auto& m) -> const std::vector<HertzMindlin::Params>& { return m.contact; },
                                   models_);
  auto add = [&](const HertzMindlin::Params& hp, double r_eff, double overlap, const ContactHistory& h) {
    e.normal += HertzMindlin::normal_energy(hp, r_eff, overlap);
    e.tangential += 0.5 * 8.0 * hp.g_eff * std::sqrt(r_eff * overlap) * norm2(h.shear);
  };
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::uint32_t k = nl.begin(i); k < nl.end(i); ++k) {
      const std::uint32_t j = nl.partner(k);
      const double overlap = p.radius[i] + p.radius[j] - norm(p.x[i] - p.x[j]);
      if (overlap <= 0) continue;
      add(contact[p.material[i] * nm + p.material[j]], p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]), overlap,
          nl.history(k));
    }
    for (std::size_t w = 0; w < walls.size(); ++w) {
      WallContact wc[kWallSlots];
      const int found = walls[w].contacts(p.x[i], p.radius[i], wc, kWallSlots);  // diagnostics: not hot
      for (int q = 0; q < found; ++q) {
        ContactHistory h{};
        for (int s = 0; s < wall_counts()[i]; ++s) {
          const WallSlot& ws = wall_slot(i, s);
          if (ws.wall == static_cast<int>(w) && ws.feature == wc[q].feature) h = ws.history;
        }
        add(contact[p.material[i] * nm + wall_material_[w]], p.radius[i], wc[q].overlap, h);
      }
    }
  }
  return e;
}

std::size_t ForceField::bytes() const {
  return (partner_share_.capacity() + share_ring_.capacity()) * sizeof(PartnerShare) + touching_.capacity() +
         near_walls_.capacity() * sizeof(std::uint32_t) + wall_hints_.capacity() * sizeof(WallGeometry::Hint) +
         wall_slots_.bytes();
}

}  // namespace grainscale::dem
