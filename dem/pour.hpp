#pragma once
// Pouring: particles enter a region at a mass rate while the simulation runs, as EDEM's dynamic
// factories do (the report filled its box with grain at 5 kg/s, then chaff at 0.1 kg/s). Every
// `interval` of simulated time the pour inserts the mass due so far, as far as the region has room;
// when it is full it waits for the particles to fall out of the way and tries again.
#include <cstdint>

#include "dem/insertion.hpp"

namespace grainscale::dem {

class Pour {
 public:
  /// `rate` in kg/s from `start` s until `batch.mass` (or `batch.count` particles) has been poured.
  Pour(ParticleBatch batch, double rate, double start, double interval);

  /// Insert what is due at the simulation's current time (call every step; acts every `interval`).
  void update(Simulation& sim, Random& rng);
  bool done() const { return done_; }
  double poured_mass() const { return mass_; }
  std::uint64_t poured_count() const { return count_; }
  std::uint64_t waits() const { return waits_; }  // times the region had no room
  const ParticleBatch& batch() const { return batch_; }

 private:
  ParticleBatch batch_;
  double rate_, start_, interval_, next_;
  double mass_ = 0;
  std::uint64_t count_ = 0, waits_ = 0;
  double particle_mass_ = 0;  // mean mass of one particle, to turn mass due into a count
  bool done_ = false;
};

}  // namespace grainscale::dem
