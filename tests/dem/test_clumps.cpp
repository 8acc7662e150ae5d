// Clumps: rigid bodies made of overlapping spheres, through the whole simulation path.
#include <omp.h>

#include <catch2/catch.hpp>

#include "parallel_everything.hpp"
#include "pass_one_loop.hpp"
#include "chaff_landing.hpp"
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>

#include "dem/rigid_rotation.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/plane.hpp"

using namespace grainscale::dem;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

Shape wheat() { return load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/wheat.yaml"); }

MaterialTable grain_and_floor(double e = 0.5, double mu = 0.5, double mu_r = 0.0) {
  MaterialTable mt;
  mt.add({"grain", 1380, 2.6e7, 0.3});
  mt.add({"floor", 1190, 7.97e8, 0.38});
  mt.set_pair(0, 0, {e, mu, mu_r, true});
  mt.set_pair(0, 1, {e, mu, mu_r, true});
  return mt;
}

}  // namespace

TEST_CASE("A clump's mass, inertia and sphere positions follow from its shape", "[dem][clump]") {
  const Shape s = wheat();
  Simulation sim(grain_and_floor(), {});
  const Quat turn = axis_angle({0, 0, 1}, M_PI / 2);  // long axis from x to y
  sim.add_clump(s, 0, 1380, {0.1, 0.2, 0.3}, turn);
  sim.setup();
  const Bodies& b = sim.bodies();
  REQUIRE(b.size() == 1);
  REQUIRE(sim.particles().size() == 7);
  const MassProperties mp = union_mass_properties(s.spheres);
  CHECK_THAT(b.mass[0], WithinRel(1380 * mp.volume, 1e-12));
  double share = 0, y_min = 1, y_max = -1;
  for (std::size_t i = 0; i < 7; ++i) {
    share += sim.particles().mass_share[i];
    y_min = std::min(y_min, sim.particles().x[i].y - sim.particles().radius[i]);
    y_max = std::max(y_max, sim.particles().x[i].y + sim.particles().radius[i]);
  }
  CHECK_THAT(share, WithinRel(b.mass[0], 1e-12));
  CHECK_THAT(y_max - y_min, WithinRel(6.7e-3, 1e-9));  // the long axis now lies along y
  CHECK_THAT(0.5 * (y_max + y_min), WithinAbs(0.2, 1e-9));
}

TEST_CASE("A clump dropped on a plane comes to rest on it: support equals weight, no creep", "[dem][clump]") {
  Simulation sim(grain_and_floor(0.3, 0.5, 0.05), {});
  sim.add_clump(wheat(), 0, 1380, {0, 0, 0.004}, axis_angle((1 / std::sqrt(2.0)) * Vec3{1, 1, 0}, 0.3));
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
  sim.setup();
  sim.run_steps(static_cast<std::uint64_t>(1.0 / sim.dt()));  // 1 s: falls, bounces, settles
  const Bodies& b = sim.bodies();
  const double weight = b.mass[0] * 9.81;
  // Support: the sum of the contact forces on the spheres balances the weight.
  Vec3 support{};
  for (std::size_t i = 0; i < sim.particles().size(); ++i) support += sim.particles().force[i];
  CHECK_THAT(support.z, WithinRel(weight, 1e-3));
  CHECK(std::abs(support.x) < 1e-3 * weight);
  // A spheroid-like clump lies on its side on one point, its widest (middle) sphere, as a spheroid
  // on a plane does; rolling resistance and friction hold it there.
  CHECK(sim.diagnostics().wall_contacts >= 1);
  // At rest, and no creep over a further second.
  CHECK(norm(b.v[0]) < 1e-4);
  const Vec3 x1 = b.x[0];
  sim.run_steps(static_cast<std::uint64_t>(1.0 / sim.dt()));
  CHECK(norm(b.x[0] - x1) < 1e-6);
}

TEST_CASE("A clump's angular velocity, read after any step, is that of its angular momentum", "[dem][clump]") {
  // The kick leaves omega to be made when it is read (Simulation::update_body_omega): a reader must
  // never see the drift's omega, from before the kick. A clump tumbling onto a plane takes torques.
  Simulation sim(grain_and_floor(0.3, 0.5, 0.05), {});
  sim.add_clump(wheat(), 0, 1380, {0, 0, 0.0032}, axis_angle((1 / std::sqrt(2.0)) * Vec3{1, 1, 0}, 0.3), {0, 0, -0.3},
                {20, -10, 5});
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
  sim.setup();
  int torqued = 0;
  for (int step = 0; step < 2000; ++step) {
    sim.run_steps(1);
    const Bodies& b = sim.bodies();
    const Vec3 w = angular_velocity(b.q[0], b.L[0], b.inertia[0]);
    REQUIRE(std::memcmp(&b.omega[0], &w, sizeof w) == 0);
    torqued += norm2(b.torque[0]) > 0;
  }
  CHECK(torqued > 10);  // it did touch the floor
}

TEST_CASE("Two clumps pressed together through several sphere pairs: equal and opposite", "[dem][clump]") {
  SimulationSettings st;
  st.gravity = {};
  st.rolling.model = RollingModel::none;
  Simulation sim(grain_and_floor(0.5, 0.5, 0.0), st);
  // Two straw pieces (seven equal spheres each) side by side, approaching; one is turned slightly and
  // spinning, so the sphere pairs touch unevenly (four at once at most, measured).
  const Shape straw = load_shape(GRAINSCALE_SOURCE_DIR "/studies/shapes/short_straw.yaml");
  sim.add_clump(straw, 0, 1380, {0, 0, 0}, {}, {0, 0.05, 0}, {0, 0, 1});
  sim.add_clump(straw, 0, 1380, {0.0003, 0.00302, 0}, axis_angle({0, 0, 1}, 0.005), {0, -0.05, 0});
  sim.setup();
  const Bodies& b = sim.bodies();
  auto momenta = [&](Vec3& lin, Vec3& ang) {
    lin = {}, ang = {};
    for (std::size_t k = 0; k < 2; ++k) {
      lin += b.mass[k] * b.v[k];
      ang += cross(b.x[k], b.mass[k] * b.v[k]) + b.L[k];
    }
  };
  Vec3 p0{}, l0{};
  momenta(p0, l0);
  std::size_t pairs = 0;
  bool checked = false;
  for (int s = 0; s < 4000; ++s) {
    sim.step();
    pairs = std::max(pairs, sim.diagnostics().contacts);
    if (!checked && sim.diagnostics().contacts >= 3) {
      // Several pairs in contact: the forces on the two bodies are equal and opposite.
      CHECK(norm(b.force[0] + b.force[1]) < 1e-12 * norm(b.force[0]));
      checked = true;
    }
  }
  CHECK(checked);
  CHECK(pairs >= 4);
  Vec3 p1{}, l1{};
  momenta(p1, l1);
  const double scale = b.mass[0] * 0.05;
  CHECK(norm(p1 - p0) < 1e-12 * scale);
  CHECK(norm(l1 - l0) < 1e-12 * (scale * 0.01 + norm(l0)));  // torques consistent: L conserved
}

TEST_CASE("A free wheat clump spinning near its intermediate axis tumbles, energy conserved", "[dem][clump]") {
  SimulationSettings st;
  st.gravity = {};
  st.time_step = 1e-4;
  Simulation sim(grain_and_floor(), st);
  // Spin about the file's y axis (a transverse axis: wheat is a near-symmetric rod, so both
  // transverse moments are close; the minor axis x is the stable one).
  sim.add_clump(wheat(), 0, 1380, {}, {}, {}, {0.5, 0, 50});
  sim.setup();
  const Bodies& b = sim.bodies();
  const double e0 = rotational_energy(b.q[0], b.L[0], b.inertia[0]);
  const Vec3 l0 = b.L[0];
  sim.run_steps(20000);  // 2 s, ~16 turns
  // Bounded O(h^2) energy error of the splitting (omega dt = 0.005); drift is checked in
  // test_rigid_rotation.cpp.
  CHECK_THAT(rotational_energy(b.q[0], b.L[0], b.inertia[0]), WithinRel(e0, 1e-5));
  CHECK(norm(b.L[0] - l0) < 1e-15 * norm(l0) + 1e-30);  // no torque: L exactly constant
}

TEST_CASE("A bed of clumps settles identically on 1 and 2 threads", "[dem][clump][determinism]") {
  const testing::ParallelEverything guard;  // every loop parallel, however small
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    Simulation sim(grain_and_floor(0.5, 0.35, 0.08), {});
    const Shape s = wheat();
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        for (int k = 0; k < 3; ++k) {
          sim.add_clump(s, 0, 1380, {0.0075 * i, 0.0075 * j, 0.003 + 0.005 * k},
                        axis_angle({0, 0, 1}, 0.3 * (i + j + k)), {0.05 * (j - 2.5), 0, 0});
        }
    sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
    sim.run_steps(2000);
    omp_set_num_threads(2);
    return std::vector<Vec3>(sim.bodies().x);
  };
  const auto one = run(1), two = run(2);
  REQUIRE(one.size() == two.size());
  CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(Vec3)) == 0);
}

TEST_CASE("The force loop's velocities of a clump's spheres, made from the body, are the spheres' own", "[dem][clump]") {
  // Since 2026-12-08 the drift no longer copies a body's v and omega into its spheres: the force loop
  // makes them from the body, v_s = v_b + omega_b x (x_s - x_b), omega_s = omega_b
  // (ForceField::read_motion_from_bodies). The same contacts evaluated with the spheres' own
  // velocities (as Simulation::particles() makes them for a reader, v_b + omega_b x R(q_b) o_s) must
  // give the same forces and torques, to round-off. Without the lever's term in the pairs' velocities
  // they differ by 4e-7 of the largest (tried). (The same term left out of the wall contacts is
  // caught by tests in test_moving_walls.cpp, test_step_control.cpp and this file, tried; not here:
  // this bed's floor contacts slide more than they turn, and their levers' term is ~1e-18 m/s.)
  SimulationSettings st;
  st.gravity = {0, 0, -400};  // pressed together within a few ms: contacts that last
  Simulation sim(grain_and_floor(0.5, 0.35, 0.08), st);
  const Shape s = wheat();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k) {  // sliding and spinning, so that the levers matter
        const double turn = (i + j + k) % 2 == 0 ? 0.0 : std::numbers::pi / 2;
        sim.add_clump(s, 0, 1380, {0.005 * i, 0.005 * j, 0.0018 + 0.0034 * k}, axis_angle({0, 0, 1}, turn),
                      {0.05 * (j - 1.5), 0, 0}, {5.0 * (i - 1.5), 0, 10});
      }
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
  sim.run_steps(1500);
  INFO(sim.diagnostics().contacts << " contacts, " << sim.diagnostics().wall_contacts << " with the floor");
  REQUIRE(sim.diagnostics().contacts > 10);
  REQUIRE(sim.diagnostics().wall_contacts > 10);
  const Bodies& b = sim.bodies();
  auto forces = [&](bool from_bodies) {
    Particles p = sim.particles();
    NeighborList nl = sim.neighbors();
    ForceField ff;
    ff.setup(sim.materials(), sim.walls(), sim.settings().rolling);
    if (from_bodies) ff.read_motion_from_bodies({b.x.data(), b.v.data(), b.omega.data()});
    const ForceDiagnostics d = ff.compute(p, nl, sim.walls(), sim.dt());
    CHECK(d.wall_contacts == sim.diagnostics().wall_contacts);
    return p;
  };
  const Particles own = forces(false), made = forces(true);
  double scale = 0, worst = 0;
  for (std::size_t i = 0; i < own.size(); ++i) {
    scale = std::max({scale, norm(own.force[i]), norm(own.torque[i]) / own.radius[i]});
    worst = std::max({worst, norm(own.force[i] - made.force[i]), norm(own.torque[i] - made.torque[i]) / own.radius[i]});
  }
  INFO("largest force " << scale << " N, largest difference " << worst << " N");
  REQUIRE(scale > 0);
  CHECK(worst <= 1e-10 * scale);
}

TEST_CASE("Clumps on a floor move the same, bit for bit, whichever sweep the force loop takes", "[dem][clump][determinism]") {
  // Beds beyond the caches sum each body as soon as its spheres' forces are final, inside the force
  // loop's sweep (AfterForces::ready); beds within them after it. A body summed a block too early (a
  // sphere of it not yet completed, or its wall contacts still waiting in the wall batch) or twice
  // would show in its velocity. 256 wheat clumps, 1,792 spheres, 28 blocks of the loop: four layers
  // of crossed clumps pressed onto the floor by a strong gravity, so that their contacts last; the
  // batches of pairs must fill for the sweep to find bodies ready before its end (the count below).
  const testing::ParallelEverything guard;  // every loop parallel, however small
  auto run = [](int threads, bool chunked) {
    const testing::PassOneLoop loop(chunked);
    omp_set_num_threads(threads);
    SimulationSettings st;
    st.gravity = {0, 0, -400};  // settles in a few ms: contacts that last
    Simulation sim(grain_and_floor(0.5, 0.35, 0.08), st);
    const Shape s = wheat();
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j)
        for (int k = 0; k < 4; ++k) {
          const double turn = (i + j + k) % 2 == 0 ? 0.0 : std::numbers::pi / 2;
          sim.add_clump(s, 0, 1380, {0.005 * i, 0.005 * j, 0.0018 + 0.0034 * k}, axis_angle({0, 0, 1}, turn), {});
        }
    sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
    sim.run_steps(1500);
    INFO(sim.diagnostics().contacts << " contacts, " << sim.diagnostics().wall_contacts << " with the floor");
    CHECK(sim.diagnostics().contacts > 64);  // batches of 64 pairs fill within the sweep
    omp_set_num_threads(2);
    std::vector<Vec3> state(sim.bodies().x);
    state.insert(state.end(), sim.bodies().v.begin(), sim.bodies().v.end());
    state.insert(state.end(), sim.bodies().L.begin(), sim.bodies().L.end());
    return state;
  };
  testing::check_same_beyond_the_caches(run, 3);
}

TEST_CASE("Clumps added to a running bed move the same, bit for bit, on 1 to 4 threads", "[dem][clump][determinism]") {
  // Each thread takes the bodies whose first sphere lies in its share of the force loop's spheres
  // (Simulation::thread_bodies); bodies added since the last list build have no sphere index yet, and
  // the drift right after an addition splits the bodies in equal shares instead. Both splits must
  // cover every body once: any body skipped or moved twice would show in its position.
  const testing::ParallelEverything guard;  // every loop parallel, however small
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    Simulation sim(grain_and_floor(0.5, 0.35, 0.08), {});
    const Shape s = wheat();
    auto layer = [&](double z, double turn) {
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
          sim.add_clump(s, 0, 1380, {0.0075 * i, 0.0075 * j, z}, axis_angle({0, 0, 1}, turn * (i + 2 * j)),
                        {0.04 * (j - 2.5), 0.02 * (i - 2.5), 0});
        }
    };
    layer(0.003, 0.3);
    sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
    sim.run_steps(400);
    for (int k = 0; k < 3; ++k) {  // a layer at a time, each dropped onto a running bed
      layer(0.012 + 0.005 * k, 0.7 + k);
      sim.run_steps(150);
    }
    omp_set_num_threads(2);
    std::vector<Vec3> state(sim.bodies().x);
    state.insert(state.end(), sim.bodies().v.begin(), sim.bodies().v.end());
    return state;
  };
  const auto one = run(1);
  for (int threads = 2; threads <= 4; ++threads) {
    INFO(threads << " threads");
    const auto many = run(threads);
    REQUIRE(one.size() == many.size());
    CHECK(std::memcmp(one.data(), many.data(), one.size() * sizeof(Vec3)) == 0);
  }
}

namespace {

/// Stage 1's bound on Omega_b^2 for every body (dem/step_stability.hpp), by brute force: every pair
/// of spheres of two bodies that overlap, every sphere against every wall, each body's compliance
/// turned into its own frame.
std::vector<double> omega2_bounds_by_brute_force(const Simulation& sim, const MaterialTable& mt) {
  const Particles& p = sim.particles();
  const Bodies& b = sim.bodies();
  auto compliance = [&](std::size_t k, const Vec3& lever, const Vec3& n) {
    const Vec3 c = rotate(conjugate(b.q[k]), cross(lever, n));
    const Vec3 I = b.inertia[k];
    return 1 / b.mass[k] + c.x * c.x / I.x + c.y * c.y / I.y + c.z * c.z / I.z;
  };
  auto e_eff = [&](int m1, int m2) { return HertzMindlin::make(mt[m1], mt[m2], mt.pair(m1, m2)).e_eff; };
  std::vector<double> bound(b.size(), 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t bi = p.body[i];
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const std::size_t bj = p.body[j];
      const double rsum = p.radius[i] + p.radius[j], dist = norm(p.x[i] - p.x[j]);
      if (bi == bj || dist >= rsum) continue;
      const Vec3 n = (1 / dist) * (p.x[i] - p.x[j]);
      const double overlap = rsum - dist;
      const Vec3 point = p.x[i] - (p.radius[i] - 0.5 * overlap) * n;
      const double s_n = 2 * e_eff(p.material[i], p.material[j]) * std::sqrt(p.radius[i] * p.radius[j] / rsum * overlap);
      const double ai = compliance(bi, point - b.x[bi], n), aj = compliance(bj, point - b.x[bj], n);
      bound[bi] += s_n * (ai + std::sqrt(ai * aj));
      bound[bj] += s_n * (aj + std::sqrt(ai * aj));
    }
    for (const Wall& w : sim.walls()) {
      WallContact wc[ForceField::kWallSlots];
      const int found = w.contacts(p.x[i], p.radius[i], wc, ForceField::kWallSlots);
      for (int q = 0; q < found; ++q) {
        const double s_n = 2 * e_eff(p.material[i], w.material()) * std::sqrt(p.radius[i] * wc[q].overlap);
        const Vec3 point = p.x[i] - (p.radius[i] - wc[q].overlap) * wc[q].normal;
        bound[bi] += s_n * compliance(bi, point - b.x[bi], wc[q].normal);
      }
    }
  }
  return bound;
}

/// 180 wheat clumps tilted every way, in a column that falls into a heap in a 44 mm square box:
/// pairs, floor and side-wall contacts.
void pour_heap(Simulation& sim) {
  const Shape s = wheat();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 5; ++k) {
        const Vec3 axis{1, 0.3 * i - 0.7, 0.2 * j + 0.1 * k};
        sim.add_clump(s, 0, 1380, {0.0072 * i, 0.0072 * j, 0.004 + 0.0075 * k},
                      axis_angle((1 / norm(axis)) * axis, 0.4 * (i + 2 * j + 3 * k)));
      }
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
  sim.add_wall("x0", std::make_shared<PlaneGeometry>(Vec3{-0.004, 0, 0}, Vec3{1, 0, 0}), 1);
  sim.add_wall("x1", std::make_shared<PlaneGeometry>(Vec3{0.04, 0, 0}, Vec3{-1, 0, 0}), 1);
  sim.add_wall("y0", std::make_shared<PlaneGeometry>(Vec3{0, -0.004, 0}, Vec3{0, 1, 0}), 1);
  sim.add_wall("y1", std::make_shared<PlaneGeometry>(Vec3{0, 0.04, 0}, Vec3{0, -1, 0}), 1);
  sim.run_steps(25000);  // fallen into a heap
}

void require_bounds_near(const std::vector<double>& got, const std::vector<double>& want) {
  REQUIRE(got.size() == want.size());
  for (std::size_t k = 0; k < want.size(); ++k) {
    INFO("body " << k);
    CHECK(got[k] == Approx(want[k]).epsilon(1e-10).margin(0));
  }
}

}  // namespace

TEST_CASE("The step-stability check of a clump heap counts every contact once, the same bit for bit on 1 to 4 threads",
          "[dem][clump][stability][determinism]") {
  // Stage 1 makes each contact's terms in parallel and adds them to every body in one fixed order
  // (dem/step_stability.cpp): any thread count gives the same per-body sums, hence the same worst body;
  // and the sums are those of a brute-force search over all spheres and walls.
  const testing::ParallelEverything guard;
  omp_set_num_threads(1);
  Simulation sim(grain_and_floor(0.5, 0.35, 0.08), {});
  const Shape s = wheat();
  pour_heap(sim);
  const StepStability one = sim.check_stability();
  const std::vector<double> bounds = sim.stability_monitor().omega2_bounds();
  INFO("contacts " << sim.diagnostics().contacts << ", wall contacts " << sim.diagnostics().wall_contacts);
  REQUIRE(sim.diagnostics().contacts > 50);
  REQUIRE(sim.diagnostics().wall_contacts > 30);
  for (int threads : {2, 3, 4}) {
    omp_set_num_threads(threads);
    const StepStability many = sim.check_stability();
    const std::vector<double>& many_bounds = sim.stability_monitor().omega2_bounds();
    REQUIRE(many_bounds.size() == bounds.size());
    CHECK(std::memcmp(many_bounds.data(), bounds.data(), bounds.size() * sizeof(double)) == 0);
    INFO(threads << " threads: margin " << many.margin << " at body " << many.body << ", 1 thread " << one.margin
                 << " at body " << one.body);
    CHECK(std::memcmp(&many.margin, &one.margin, sizeof(double)) == 0);
    CHECK(std::memcmp(&many.zeta, &one.zeta, sizeof(double)) == 0);
    CHECK(many.body == one.body);
    CHECK(many.contacts == one.contacts);
  }
  const std::vector<double> brute = omega2_bounds_by_brute_force(sim, grain_and_floor(0.5, 0.35, 0.08));
  REQUIRE(std::count_if(brute.begin(), brute.end(), [](double w) { return w > 0; }) > 80);  // 97 of 180 clumps
  require_bounds_near(bounds, brute);

  // A clump added against a side wall, away from the heap: until the next step neither the
  // neighbour list nor the bodies' sphere index knows its spheres. The check finds its wall contacts.
  sim.add_clump(s, 0, 1380, {0.0398, 0.02, 0.06}, axis_angle({0, 1, 0}, 1.5707963));
  omp_set_num_threads(1);
  sim.check_stability();
  const std::vector<double> added = sim.stability_monitor().omega2_bounds();
  omp_set_num_threads(3);
  sim.check_stability();
  const std::vector<double>& added_3 = sim.stability_monitor().omega2_bounds();
  REQUIRE(added_3.size() == added.size());
  CHECK(std::memcmp(added_3.data(), added.data(), added.size() * sizeof(double)) == 0);
  CHECK(added.back() > 0);  // the new clump touches the wall
  require_bounds_near(added, omega2_bounds_by_brute_force(sim, grain_and_floor(0.5, 0.35, 0.08)));
  omp_set_num_threads(2);
}

TEST_CASE("Stage 2 of the step-stability check: each suspect's contacts from its own spheres, eigenproblems only where "
          "the worst can be, the same worst body", "[dem][clump][stability]") {
  // dem/step_stability.cpp, stage 2, two short cuts against the reference (every contact walked again,
  // every suspect's 6 x 6 eigenproblem solved):
  //  - each suspect's contacts come from its spheres' neighbour-list rows and reverse ranges, in the
  //    order of the walk over every contact: the same matrices, so the same margins bit for bit;
  //  - a suspect whose bound on its margin (its stage-1 margin, or the Gershgorin bound of its 6 x 6
  //    matrices) is below the worst found so far is not solved: the bound is above its margin, and
  //    the worst body is the same.
  // The step is raised until most of the heap's bodies are suspects.
  const testing::ParallelEverything guard;
  omp_set_num_threads(1);
  Simulation sim(grain_and_floor(0.5, 0.35, 0.08), {});
  pour_heap(sim);
  auto assess = [&](StepStabilityMonitor& m, double dt) {
    return m.assess(sim.particles(), sim.bodies(), sim.neighbors(), sim.walls(), sim.force_field(), dt);
  };
  StepStabilityMonitor probe;
  assess(probe, sim.dt());
  std::vector<double> m = probe.margins();
  m.erase(std::remove(m.begin(), m.end(), 0.0), m.end());
  REQUIRE(m.size() > 80);
  std::sort(m.begin(), m.end());
  const double dt = sim.dt() * 2 * StepStabilityMonitor::kRefineAbove / m[m.size() / 2];  // the median's bound at 1
  std::size_t sure_suspects = 0;  // margin >= Omega dt / 2 for any damping
  for (const double w2 : probe.omega2_bounds()) sure_suspects += std::sqrt(w2) * dt > 2 * StepStabilityMonitor::kRefineAbove;
  INFO("dt " << dt << " s, " << sure_suspects << " bodies surely suspects of " << m.size() << " touching");
  REQUIRE(sure_suspects > 40);
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    StepStabilityMonitor fast, by_body, reference;
    by_body.use_reference_stage2(true, false);
    reference.use_reference_stage2(true, true);
    const StepStability f = assess(fast, dt), a = assess(by_body, dt), r = assess(reference, dt);
    REQUIRE(r.refined);
    REQUIRE(reference.refined() >= sure_suspects);
    REQUIRE(by_body.refined() == reference.refined());
    REQUIRE(by_body.margins().size() == reference.margins().size());
    std::size_t same = 0, bounded = 0;
    for (std::size_t k = 0; k < reference.margins().size(); ++k) {
      same += std::memcmp(&by_body.margins()[k], &reference.margins()[k], sizeof(double)) == 0;
      // (a bound, up to round-off: it is exact for a body whose one contact pushes along an axis)
      bounded += fast.margins()[k] >= reference.margins()[k] * (1 - 1e-12);
    }
    CHECK(same == reference.margins().size());
    CHECK(bounded == reference.margins().size());
    INFO(fast.refined() << " of " << reference.refined() << " suspects solved");
    CHECK(fast.refined() < reference.refined() / 4);
    for (const StepStability* x : {&a, &f}) {
      CHECK(std::memcmp(&x->margin, &r.margin, sizeof(double)) == 0);
      CHECK(std::memcmp(&x->zeta, &r.zeta, sizeof(double)) == 0);
      CHECK(x->body == r.body);
      CHECK(x->contacts == r.contacts);
      CHECK(x->refined);
    }
  }
  omp_set_num_threads(2);
}

using testing::land_on_chaff;
using testing::Landing;

TEST_CASE("A wheat grain landing on a chaff flake: converged at 10 % of the Rayleigh time", "[dem][clump]") {
  // At 10 % and 5 % of the Rayleigh time the results agree: the flake deforms by 41 % of its radius
  // (real Hertz deformation of so soft a material) and moves off at 0.68 m/s.
  const Landing l10 = land_on_chaff(0.1), l05 = land_on_chaff(0.05);
  INFO("10 %: " << l10.flake_speed << " m/s, " << l10.overlap << "; 5 %: " << l05.flake_speed << " m/s, " << l05.overlap);
  CHECK_THAT(l10.flake_speed, WithinRel(l05.flake_speed, 0.02));
  CHECK_THAT(l10.overlap, WithinRel(l05.overlap, 0.02));
  CHECK(l05.flake_speed < 1.0);  // no ejection
  CHECK(l05.overlap > 0.3);      // deep but physical deformation
  CHECK(l10.worst.margin < 1);
}

TEST_CASE("The per-body step-stability check predicts the chaff sandwich instability", "[dem][clump][stability]") {
  // At the default 20 % of the Rayleigh time the squeezed flake is shot out; every single contact
  // is well resolved (omega dt ~ 0.3), but the flake's fastest mode with nine contacts and heavy
  // damping (e = 0.1 against the floor) is not. At 15 % it stays put.
  const Landing unstable = land_on_chaff(0.2), stable = land_on_chaff(0.15);
  INFO("20 %: " << unstable.flake_speed << " m/s, margin " << unstable.worst.margin << "; 15 %: " << stable.flake_speed
                << " m/s, margin " << stable.worst.margin);
  CHECK(unstable.flake_speed > 2.0);
  CHECK(unstable.worst.margin > 1.0);
  CHECK(unstable.worst.body == 0);  // the flake
  CHECK(unstable.worst.refined);
  CHECK(stable.flake_speed < 1.0);
  CHECK(stable.worst.margin < 1.0);
}
