#pragma once
// The Verlet skin chosen afresh at every neighbour-list build (time.skin: 0, the default).
//
// The list holds every pair closer than r_i + r_j + skin and stays exact until some sphere has moved
// skin/2 (Allen & Tildesley 2017, Sec. 5.3), so the skin trades two costs:
//   - every listed pair not in contact costs a distance test every step; the number of such pairs
//     grows with the skin (a settled bed of 7-sphere clumps, 0.43 contacts per sphere: 2.74 list
//     entries per sphere at skin 0.2 r_max, 0.51 at r_max / 160, the floor below; 15.5 -> 25.9 M
//     sphere-steps/s on one core, docs/performance.md "the adaptive skin");
//   - a build (sort, renumber, list) costs a few steps' work, and comes every skin / (2 v_max dt)
//     steps: where everything moves (a box in mid-swing) builds are what a thin skin costs, which
//     is why kSteps is not smaller (there, with the builds of the time, 20 was 15 % slower than 40,
//     and 40 to 160 within 5 %; since builds scan once, 40 and 160 are level).
// A bed shaken slowly moves far less than a skin of 0.2 r_max per few dozen steps, so a fixed skin
// sized for pouring wastes most of the distance tests. The skin is therefore sized so that the list
// lasts about kSteps steps at the present speed:
//   skin(v) = clamp(2 kSteps v dt, kMinFraction skin_max, skin_max),
// skin_max = 0.2 r_max (the fixed skin grainscale used before; cells stay no wider than they were).
// Each sphere gets a skin of its own (the list's rule for that: dem/neighbor_list.hpp):
//   - the common skin, skin(v_c), where v_c is the speed all but the fastest kFastShare of the
//     spheres keep under, for every sphere up to v_c;
//   - own(v_i) = clamp(2 kOwnSteps v_i dt, ...) for a sphere faster than v_c, and the same for every
//     sphere in its own and the adjacent cells (the ones it may strike before the next build: a
//     sphere struck from rest would otherwise outrun the common skin within a few steps; the bed
//     below made 25 list builds in 600 steps without this, 20 with it). kOwnSteps = 2 kSteps: these
//     few spheres decide how often the list is rebuilt (the rest last longer), and their entries are
//     few, so they are sized to last twice as long (in-process A/B, docs/performance.md, fourteenth
//     session: the platform box mid-rise +3.5 to +5 %, the 10^5 bed +0.3 to +4 %, the 10^3 bed
//     +1.5 %; the clump bed has none, unchanged).
// So a few fast spheres no longer thicken every sphere's list. A bed that has come to rest still
// has some (the 10^5-sphere bed of bench/run_scaling.sh after 0.8 s: the median sphere at 0.08 mm/s,
// a few rolling over the surface at 0.1-0.2 m/s); under one skin for all, the fastest set the skin
// at skin_max: 2.82 list entries per sphere against 1.99 with skins of their own (1.88 contacts),
// each step ~6 % slower on one thread (the two codes alternated, docs/performance.md). And a larger
// bed has a faster outlier, so one skin for all made the cost per sphere grow with N. Where even the fastest sphere's skin is the
// floor, all share it, and the list is the same bit for bit as under one skin.
// A list that is never stale (a bed come to rest) would keep the skins of its build for ever, so
// every kCheckEvery steps (counted from the start: restarts see the same steps) the common skin is
// chosen again, and the list rebuilt if it is under half the build's.
// Speeds are taken in the list's frame (dem/list_frame.hpp): a bed carried by its turning box is
// slow there, however fast the box moves.
// The choice affects cost only, never which contacts are found: the list is rebuilt whenever a
// sphere has moved half its skin of the build, whatever that skin was. It depends only on the state
// at the build (no timers, no thread count), so runs stay reproducible bit for bit, checkpoints included.
#include <algorithm>

namespace grainscale::dem {

struct AdaptiveSkin {
  /// Steps a list should last at a sphere's speed at its build.
  static constexpr double kSteps = 40;
  /// The same for a sphere faster than the common speed, which gets a skin of its own.
  static constexpr double kOwnSteps = 2 * kSteps;
  /// Smallest skin, as a fraction of skin_max: a bed at rest still needs a list that lasts.
  static constexpr double kMinFraction = 1.0 / 32;

  /// The share of the spheres, the fastest, that get a skin of their own (see above).
  static constexpr double kFastShare = 0.01;

  /// Steps between checks whether a list still valid should be rebuilt with a smaller skin.
  static constexpr unsigned kCheckEvery = 100;

  /// The skin for a build of a sphere of speed v (m/s; for the common skin v_c), given the time step
  /// dt (s) and the largest skin allowed (m).
  static double choose(double v, double dt, double skin_max) {
    return std::clamp(2.0 * kSteps * v * dt, kMinFraction * skin_max, skin_max);
  }
  /// The own skin of a sphere of speed v, faster than the common speed.
  static double choose_own(double v, double dt, double skin_max) {
    return std::clamp(2.0 * kOwnSteps * v * dt, kMinFraction * skin_max, skin_max);
  }
  /// Worth a build before the list is stale? (The common skins, of the build and chosen now.)
  static bool shrink(double skin_now, double skin_chosen) { return skin_chosen < 0.5 * skin_now; }
};

}  // namespace grainscale::dem
