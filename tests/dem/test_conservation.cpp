// Conservation laws of the integrator and the contact forces.
//  * e = 1, no friction: Hertz contacts are conservative and velocity Verlet is symplectic, so the
//    total energy (kinetic + elastic) must not drift over 100,000 steps in a dense box. The Hertz
//    force is not smooth at contact onset (F ~ delta^(3/2)), so each collision leaves an energy error
//    of high order in dt (Danby et al. 2013); measured here: about dt^3. At 5 % of the Rayleigh time
//    and 0.5 m/s collisions the drift is 4e-5; at the default 20 % it is 3e-3.
//  * Pair forces are equal and opposite, so total linear momentum is conserved to round-off with
//    every dissipative ingredient switched on; with pair-antisymmetric torques (no rolling model, or
//    EPSD) angular momentum is conserved too. EDEM's constant-torque model is per body and is not.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#include <tuple>

#include "dem/simulation.hpp"
#include "dem/walls/box.hpp"

using namespace grainscale::dem;

namespace {

MaterialTable table(double e, double mu, double mu_r) {
  MaterialTable mt;
  mt.add({"grain", 1000, 1e7, 0.3});
  mt.add({"steel", 7800, 8e10, 0.3});
  mt.set_pair(0, 0, {e, mu, mu_r, true});
  mt.set_pair(0, 1, {e, mu, mu_r, true});
  return mt;
}

/// n^3 spheres of radius r on a cubic lattice with spacing `spacing`, random velocities up to v,
/// plus a velocity `converge` (1/s) times the distance towards the lattice centre.
void lattice(Simulation& sim, int n, double r, double spacing, double v, unsigned seed, double converge = 0) {
  const double c = 0.5 * n * spacing;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vec3 x{(i + 0.5) * spacing, (j + 0.5) * spacing, (k + 0.5) * spacing};
        const Vec3 inward = converge * (Vec3{c, c, c} - x);
        sim.add_sphere(0, r * (1 + 0.05 * u(rng)), x, inward + Vec3{v * u(rng), v * u(rng), v * u(rng)},
                       {50 * u(rng), 50 * u(rng), 50 * u(rng)});
      }
}

}  // namespace

namespace {

struct EnergyRun {
  double drift, worst;  // |E_end - E_0| and max |E - E_0|, relative to the initial kinetic energy
  std::uint64_t builds;
};

/// 216 elastic frictionless spheres colliding at ~0.5 m/s in a closed box under gravity.
EnergyRun elastic_box(double dt_fraction, double seconds, unsigned seed = 7) {
  SimulationSettings st;
  st.gravity = {0, 0, -9.81};
  st.rolling.model = RollingModel::none;
  st.time_step_fraction = dt_fraction;
  Simulation sim(table(1.0, 0.0, 0.0), st);
  const int n = 6;
  const double r = 0.005, spacing = 2.1 * r, side = n * spacing;
  lattice(sim, n, r, spacing, 0.5, seed);
  sim.add_wall("box", std::make_shared<BoxGeometry>(Vec3{0, 0, 0}, Vec3{side, side, side}), 1);
  sim.setup();
  const double e0 = sim.energy().total();
  const double scale = sim.energy().kinetic_translation + sim.energy().kinetic_rotation;
  const auto steps = static_cast<std::uint64_t>(seconds / sim.dt());
  double worst = 0;
  for (int block = 0; block < 100; ++block) {
    sim.run_steps(steps / 100);
    worst = std::max(worst, std::abs(sim.energy().total() - e0));
  }
  return {std::abs(sim.energy().total() - e0) / scale, worst / scale, sim.neighbors().builds()};
}

}  // namespace

TEST_CASE("Elastic frictionless spheres in a dense box conserve energy over 100,000 steps", "[dem][conservation]") {
  const double rayleigh = 1.69e-4;  // s, for r = 5 mm, G = 1e7 Pa, rho = 1000, nu = 0.3
  const EnergyRun run = elastic_box(0.05, 100'000 * 0.05 * rayleigh);
  INFO("relative drift " << run.drift << ", worst excursion " << run.worst);
  CHECK(run.drift < 1e-4);
  CHECK(run.worst < 2e-4);
  CHECK(run.builds > 10);  // the list was rebuilt (and particles reordered) many times
}

TEST_CASE("The energy error of collisions converges at second order in the time step", "[dem][conservation]") {
  // The worst energy error of one box is a statistic of a chaotic run: a change in the last bit of
  // one force (the order a sum is taken in) gives another trajectory, and one box's observed order
  // then ranges from 1.2 to 3.1 (six lattices: 2.38, 1.20, 2.81, 2.07, 3.14, 2.23 from dt 0.2 to 0.1
  // of the Rayleigh time; 1.84-2.67 from 0.1 to 0.05). Summed over six lattices it is 2.28 and 2.30.
  const double seconds = 0.4;
  double coarse = 0, fine = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    coarse += elastic_box(0.2, seconds, seed).worst;
    fine += elastic_box(0.1, seconds, seed).worst;
  }
  const double rate = std::log2(coarse / fine);
  INFO("worst energy error summed over six boxes " << coarse << " -> " << fine << ", observed order " << rate);
  REQUIRE(rate > 2.0 - 0.1);
}

TEST_CASE("Colliding spheres without walls conserve momentum to round-off", "[dem][conservation]") {
  const RollingModel model = GENERATE(RollingModel::none, RollingModel::epsd, RollingModel::constant_torque);
  SimulationSettings st;
  st.gravity = {0, 0, 0};
  st.rolling.model = model;
  Simulation sim(table(0.5, 0.5, 0.1), st);
  lattice(sim, 5, 0.005, 0.0106, 0.2, 11, 10.0);  // converging: the cluster collides, then spreads
  sim.setup();

  auto momentum = [&] {
    const Particles& p = sim.particles();
    Vec3 lin, ang;
    double ref = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      lin += p.mass[i] * p.v[i];
      ang += cross(p.x[i], p.mass[i] * p.v[i]) + p.inertia[i] * p.omega[i];
      ref += p.mass[i] * norm(p.v[i]);
    }
    return std::tuple{lin, ang, ref};
  };
  const auto [p0, l0, ref] = momentum();
  std::size_t contacts = 0;
  for (int block = 0; block < 30; ++block) {
    sim.run_steps(100);
    contacts += sim.diagnostics().contacts;
  }
  const auto [p1, l1, ref1] = momentum();
  INFO("model " << static_cast<int>(model));
  REQUIRE(contacts > 100);
  CHECK(norm(p1 - p0) < 1e-13 * ref);
  const double ang_scale = ref * 0.05;  // momentum x system size
  if (model == RollingModel::constant_torque) {
    CHECK(norm(l1 - l0) > 1e-9 * ang_scale);  // per-body torques: not conserved (documents the model)
  } else {
    CHECK(norm(l1 - l0) < 1e-12 * ang_scale);
  }
}
