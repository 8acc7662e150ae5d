#include "dem/pour.hpp"

#include <cmath>
#include <numbers>

#include "dem/wall_clearance.hpp"

namespace grainscale::dem {

Pour::Pour(ParticleBatch batch, double rate, double start, double interval)
    : batch_(std::move(batch)), rate_(rate), start_(start), interval_(interval), next_(start) {
  batch_.best_effort = true;
  batch_.count = 0;
}

void Pour::update(Simulation& sim, Random& rng) {
  if (done_ || sim.time() + 1e-12 < next_) return;
  next_ += interval_;
  if (particle_mass_ == 0) {
    const double density = batch_.density > 0 ? batch_.density : sim.materials()[batch_.material].density;
    const double r = 0.5 * batch_.diameter;
    particle_mass_ = batch_.shape ? density * union_mass_properties(batch_.shape->spheres).volume
                                  : density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
  const double total = batch_.mass;
  const double due = std::min(total, rate_ * (sim.time() - start_ + interval_));
  const auto n = static_cast<std::uint64_t>(std::floor((due - mass_) / particle_mass_ + 0.5));
  if (n == 0) return;
  ParticleBatch now = batch_;
  now.count = n;
  const std::size_t first = sim.particles().size();
  const InsertionReport r = insert_particles(sim, now, rng);
  require_clear_of_walls(sim, first, batch_.label + ".region");
  mass_ += r.mass;
  count_ += r.placed;
  if (r.full) ++waits_;
  if (mass_ >= total - 0.5 * particle_mass_) done_ = true;
}

}  // namespace grainscale::dem
