// A bed of loose spheres keeps its bodies' position, velocity, angular velocity, force and torque in
// its spheres' arrays (Simulation::spheres_hold_bodies_) instead of a copy of their own that the
// spheres follow every step. Checked against that copy (SimulationSettings::loose_bodies_in_spheres
// = false), bit for bit: through list builds, reads of the bodies between steps, a sphere added to
// the running bed (the bodies take their state back until the next build), and a checkpoint
// restored into a fresh simulation.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <vector>

#include "barley_box_fixture.hpp"
#include "checkpoint_fixture.hpp"
#include "dem/checkpoint.hpp"
#include "parallel_everything.hpp"

using namespace grainscale::dem;

namespace {

/// Every body's and sphere's dynamic state, by id: what a step or an output reads.
std::vector<double> state_of(const Simulation& sim) {
  const Bodies& b = sim.bodies();
  const Particles& p = sim.particles();
  std::vector<double> out;
  auto put = [&](const Vec3& v) { out.insert(out.end(), {v.x, v.y, v.z}); };
  auto put_q = [&](const Quat& q) { out.insert(out.end(), {q.w, q.x, q.y, q.z}); };
  for (std::size_t k : b.indices_by_id()) {
    put(b.x[k]), put(b.v[k]), put(b.L[k]), put(b.omega[k]), put(b.force[k]), put(b.torque[k]), put_q(b.q[k]);
  }
  std::vector<std::size_t> slot(p.size());
  for (std::size_t s = 0; s < p.size(); ++s) slot[p.id[s]] = s;
  for (std::size_t s : slot) put(p.x[s]), put(p.v[s]), put(p.omega[s]), put(p.force[s]), put(p.torque[s]), put_q(p.q[s]);
  return out;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

Simulation bed(RollingModel model, bool in_spheres) {
  SimulationSettings st;
  st.loose_bodies_in_spheres = in_spheres;
  return testing::barley_box(model, 6, 6, 8, 7, st);
}

}  // namespace

TEST_CASE("A bed of loose spheres whose spheres hold their bodies' state moves as one whose bodies keep a copy, "
          "bit for bit",
          "[dem][determinism]") {
  const testing::ParallelEverything guard;  // every loop parallel, however small
  const RollingModel model = GENERATE(RollingModel::constant_torque, RollingModel::epsd);
  const int threads = GENERATE(1, 2);
  INFO("rolling model " << static_cast<int>(model) << ", " << threads << " threads");
  omp_set_num_threads(threads);
  Simulation held = bed(model, true), copied = bed(model, false);

  // Falling, colliding, spinning: list builds on the way. The held bed's bodies are read every ten
  // steps (each read makes their copy), the other's not at all.
  for (int i = 0; i < 30; ++i) {
    held.run_steps(100);
    (void)held.bodies();
  }
  copied.run_steps(3000);
  INFO(held.diagnostics().contacts << " contacts, " << held.diagnostics().wall_contacts << " wall contacts");
  REQUIRE(held.diagnostics().contacts > 100);
  REQUIRE(held.diagnostics().wall_contacts > 30);
  REQUIRE(held.loose_bodies_in_spheres());
  REQUIRE_FALSE(copied.loose_bodies_in_spheres());
  CHECK(same_bits(state_of(held), state_of(copied)));
  CHECK(held.energy().total() == copied.energy().total());

  // A sphere poured onto the running bed, unread since its last steps: the bodies take their state
  // back until the next build (read at once, and after steps).
  held.run_steps(53), copied.run_steps(53);
  for (Simulation* sim : {&held, &copied}) sim->add_sphere(0, 0.003, {0.02, 0.02, 0.12}, {0, 0, -0.5});
  CHECK_FALSE(held.loose_bodies_in_spheres());
  held.run_steps(200), copied.run_steps(200);
  CHECK(held.loose_bodies_in_spheres());
  CHECK(same_bits(state_of(held), state_of(copied)));
  held.run_steps(48), copied.run_steps(48);  // (to step 3,301: no stability check, which reads the bodies, at its end)
  for (Simulation* sim : {&held, &copied}) sim->add_sphere(0, 0.003, {0.03, 0.02, 0.12}, {0, 0, -0.5});
  CHECK(same_bits(state_of(held), state_of(copied)));
  held.run_steps(100), copied.run_steps(100);
  CHECK(same_bits(state_of(held), state_of(copied)));

  // Restarted from a checkpoint of the held bed, into a fresh simulation of each kind and into the
  // held one itself, running: the state's bodies are what it holds, its spheres' position, velocity
  // and angular velocity only follow them (put off here, they must not matter).
  testing::CheckpointTempDir dir;
  write_checkpoint(dir / "held.h5", held);
  auto off_spheres = [&] {
    Checkpoint c = read_checkpoint(dir / "held.h5");
    Particles& p = c.simulation.particles;
    for (std::size_t s = 0; s < p.size(); ++s) p.x[s].z += 1e-9, p.v[s].x += 1, p.omega[s].y -= 2;
    return c;
  };
  Simulation restored_held = bed(model, true), restored_copied = bed(model, false);
  restore_checkpoint(off_spheres(), restored_held);
  restore_checkpoint(off_spheres(), restored_copied);
  restore_checkpoint(off_spheres(), held);
  CHECK(restored_held.loose_bodies_in_spheres());
  CHECK(held.loose_bodies_in_spheres());
  for (Simulation* sim : {&held, &copied, &restored_held, &restored_copied}) sim->run_steps(300);
  const std::vector<double> want = state_of(copied);
  CHECK(same_bits(state_of(held), want));
  CHECK(same_bits(state_of(restored_held), want));
  CHECK(same_bits(state_of(restored_copied), want));
  omp_set_num_threads(2);
}
