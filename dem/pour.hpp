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

  /// What changes as the pour runs: what a checkpoint stores (dem/checkpoint.hpp).
  struct State {
    double next = 0;           // s: time of the next insertion
    double mass = 0;           // kg poured so far
    double particle_mass = 0;  // kg, 0 until the first insertion computes it
    std::uint64_t count = 0, waits = 0;
    bool done = false;
  };
  State state() const { return {next_, mass_, particle_mass_, count_, waits_, done_}; }
  void restore(const State& s) {
    next_ = s.next, mass_ = s.mass, particle_mass_ = s.particle_mass, count_ = s.count, waits_ = s.waits, done_ = s.done;
  }

 private:
  ParticleBatch batch_;
  double rate_, start_, interval_, next_;
  double mass_ = 0;
  std::uint64_t count_ = 0, waits_ = 0;
  double particle_mass_ = 0;  // mean mass of one particle, to turn mass due into a count
  bool done_ = false;
};

}  // namespace grainscale::dem
