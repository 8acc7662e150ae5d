// Pass 2 of the force loop evaluates sphere-wall contacts a WallBatch at a time, vectorised
// (dem/wall_batch.hpp). It must give exactly what one contact at a time gives: the same bits for
// forces, torques and histories, for every rolling model, sticking and sliding, fresh and loaded
// histories, spinning and still spheres, still and moving walls; and the force loop must add each
// contact to its sphere in the order the contacts were found, across batches.
#include <catch2/catch.hpp>

#include <cstring>
#include <limits>
#include <memory>
#include <random>

#include "dem/contact/rolling_constant_torque.hpp"
#include "dem/contact/rolling_epsd.hpp"
#include "dem/contact/rolling_none.hpp"
#include "dem/force_field.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/particles.hpp"
#include "dem/wall_batch.hpp"
#include "dem/walls/box.hpp"

#include "batch_test_support.hpp"
#include "list_fixture.hpp"

using namespace grainscale::dem;
using grainscale::dem::testing::rolling_params;
using grainscale::dem::testing::same_bits;
using grainscale::dem::testing::sliding;

namespace {

struct OneContact {
  Vec3 force, torque;
  ContactHistory history;
};

/// One wall contact as the force loop evaluated it before batching, out of line so that the
/// compiler cannot vectorise it with the batch: the kinematics of a sphere (centre x, velocity v,
/// angular velocity w, radius r, mass m, moment of inertia i) touching a wall of pose `pose`.
template <class Rolling>
[[gnu::noinline]] OneContact one_contact(const HertzMindlin::Params& hm, const typename Rolling::Params& rp,
                                         const WallContact& wc, const WallPose& pose, const Vec3& v, const Vec3& w,
                                         double r, double m, double i, ContactHistory h, double dt) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ContactKinematics c;
  c.n = wc.normal;
  c.overlap = wc.overlap;
  c.lever_i = r - c.overlap;
  c.lever_j = 0;
  c.omega_i = w;
  c.omega_j = pose.angular_velocity;
  c.v_rel = v - c.lever_i * cross(w, c.n) - pose.surface_velocity(wc.point);
  c.r_eff = r;
  c.mass_i = c.m_eff = m;
  c.mass_j = kInf;
  c.inertia_i = i;
  c.inertia_j = kInf;
  c.dt = dt;
  const ContactForce f = HertzMindlin::evaluate(hm, c, h);
  Vec3 ti, tj;
  Rolling::evaluate(rp, c, f, h, ti, tj);
  return {f.force, ti - c.lever_i * cross(c.n, f.tangential), h};
}


}  // namespace

TEMPLATE_TEST_CASE("A vectorised batch of wall contacts gives one contact at a time's numbers bit for bit",
                   "[dem][contact][walls]", NoRolling, ConstantTorqueRolling, EpsdRolling) {
  std::mt19937_64 rng(GENERATE(1u, 2u));
  std::uniform_real_distribution<double> u(-1, 1);
  const Material grain{"grain", 1380, 2.6e6, 0.3}, steel{"steel", 7800, 2e11, 0.3};
  const PairProperties pp{0.5, 0.35, 0.08, true};
  const double dt = 2e-6;
  WallBatch<TestType> b;
  b.size = WallBatch<TestType>::kCapacity - 3;  // not a whole number of vector lanes
  std::vector<OneContact> expected;
  for (int k = 0; k < b.size; ++k) {
    const double r = 0.002 * (1.5 + u(rng));
    const Vec3 dir{u(rng), u(rng), u(rng)};
    WallContact wc;
    wc.normal = (1.0 / norm(dir)) * dir;
    wc.overlap = 0.02 * r * (1 + u(rng));
    const Vec3 x{u(rng), u(rng), u(rng)};
    wc.point = x - (r - wc.overlap) * wc.normal;
    WallPose pose;
    if (k % 3 == 0) pose.velocity = 0.1 * Vec3{u(rng), u(rng), u(rng)}, pose.angular_velocity = Vec3{u(rng), u(rng), u(rng)};
    const bool still = k % 5 == 0;  // spheres not turning at all (the rolling models' w = 0 case)
    const Vec3 v = 0.1 * Vec3{u(rng), u(rng), u(rng)}, w = (still ? 0.0 : 50.0) * Vec3{u(rng), u(rng), u(rng)};
    const double m = 1e-5 * (1.5 + u(rng)), inertia = 1e-11 * (1.5 + u(rng));
    const HertzMindlin::Params hm = HertzMindlin::make(grain, k % 2 ? grain : steel, pp);
    const typename TestType::Params rp = rolling_params<TestType>(pp);
    // Fresh contacts (zero history), small springs (sticking) and large ones (sliding).
    const double s = k % 4 == 0 ? 0.0 : (k % 4 == 1 ? 1e-7 : 1e-4);
    const double e = k % 2 ? 0.0 : 1e-6;
    const ContactHistory h{s * Vec3{u(rng), u(rng), u(rng)}, e * Vec3{u(rng), u(rng), u(rng)}};
    expected.push_back(one_contact<TestType>(hm, rp, wc, pose, v, w, r, m, inertia, h, dt));

    // As pass 2 queues it (dem/force_field.cpp, add_wall_contacts).
    const Vec3 v_rel = v - (r - wc.overlap) * cross(w, wc.normal) - pose.surface_velocity(wc.point);
    b.nx[k] = wc.normal.x, b.ny[k] = wc.normal.y, b.nz[k] = wc.normal.z, b.overlap[k] = wc.overlap, b.ri[k] = r;
    b.vx[k] = v_rel.x, b.vy[k] = v_rel.y, b.vz[k] = v_rel.z;
    b.wix[k] = w.x, b.wiy[k] = w.y, b.wiz[k] = w.z;
    b.wjx[k] = pose.angular_velocity.x, b.wjy[k] = pose.angular_velocity.y, b.wjz[k] = pose.angular_velocity.z;
    b.mi[k] = m, b.ii[k] = inertia, b.contact[k] = hm, b.rolling[k] = rp;
    b.sx[k] = h.shear.x, b.sy[k] = h.shear.y, b.sz[k] = h.shear.z;
    b.rx[k] = h.rolling.x, b.ry[k] = h.rolling.y, b.rz[k] = h.rolling.z;
  }

  b.evaluate(dt);

  int slides = 0;
  for (int k = 0; k < b.size; ++k) {
    INFO("contact " << k);
    const OneContact& e = expected[k];
    CHECK(same_bits(Vec3{b.fx[k], b.fy[k], b.fz[k]}, e.force));
    CHECK(same_bits(Vec3{b.tx[k], b.ty[k], b.tz[k]}, e.torque));
    CHECK(same_bits(Vec3{b.sx[k], b.sy[k], b.sz[k]}, e.history.shear));
    CHECK(same_bits(Vec3{b.rx[k], b.ry[k], b.rz[k]}, e.history.rolling));
    slides += sliding(Vec3{b.fx[k], b.fy[k], b.fz[k]}, Vec3{b.nx[k], b.ny[k], b.nz[k]}, pp.friction);
  }
  INFO(slides << " of " << b.size << " contacts sliding");
  CHECK(slides > 3);  // the Coulomb branch is taken by some, not all
  CHECK(slides < b.size - 3);
}

TEST_CASE("Spheres on a moving box's floor and in its corners get the one-at-a-time loop's wall forces bit for bit",
          "[dem][contact][walls]") {
  // 150 spheres pressed into the floor of a box whose frame moves and turns, some in its corners
  // (three contacts each): more wall contacts than a batch holds, so they span several flushes. They
  // are spaced apart (no pair contacts), so each sphere's force and torque are its wall contacts
  // summed in the order the walls report them, starting from zero. Two steps: fresh histories, then
  // loaded ones (matched by wall and feature), with the second step's positions moved a little.
  MaterialTable materials;
  const int grain = materials.add({"grain", 1380, 2.6e6, 0.3});
  const int perspex = materials.add({"perspex", 1190, 3.2e9, 0.35});
  materials.set_pair(grain, perspex, {0.5, 0.45, 0.08, true});
  materials.set_pair(grain, grain, {0.5, 0.45, 0.08, true});
  const double r = 0.002, side = 0.1, skin = 0.0004, dt = 2e-6;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  Particles p;
  int id = 0;
  auto place = [&](double x, double y, bool corner) {
    const double sink = 5e-5 * (1.5 + u(rng));
    const double cx = corner ? (x < side / 2 ? r - sink : side - r + sink) : x;
    const double cy = corner ? (y < side / 2 ? r - sink : side - r + sink) : y;
    p.add_sphere(id++, grain, r, 1380, {cx, cy, r - sink}, 0.05 * Vec3{u(rng), u(rng), u(rng)},
                 30 * Vec3{u(rng), u(rng), u(rng)});
  };
  for (int a = 0; a < 4; ++a) place(a % 2 ? side : 0, a / 2 ? side : 0, true);
  for (int gx = 0; gx < 12; ++gx)
    for (int gy = 0; gy < 12; ++gy) place(0.008 + 0.0075 * gx, 0.008 + 0.0075 * gy, false);
  REQUIRE(p.size() > 2 * WallBatch<ConstantTorqueRolling>::kCapacity);

  std::vector<Wall> walls;
  walls.emplace_back("box", std::make_shared<BoxGeometry>(Vec3{0, 0, 0}, Vec3{side, side, side}), perspex);
  WallPose pose;
  pose.velocity = {0.02, -0.01, 0.005};
  pose.angular_velocity = {0.3, -0.2, 0.5};  // the frame turns: the surface velocity varies over the floor
  walls[0].set_pose(pose);

  NeighborList nl;
  grainscale::dem::testing::build_list(nl, p, skin);
  ForceField ff;
  ff.setup(materials, walls, RollingSettings{});

  const HertzMindlin::Params hm = HertzMindlin::make(materials[grain], materials[perspex], materials.pair(grain, perspex));
  const ConstantTorqueRolling::Params roll = ConstantTorqueRolling::make(materials.pair(grain, perspex));
  for (int step = 0; step < 2; ++step) {
    INFO("step " << step);
    if (step == 1) {
      for (std::size_t i = 0; i < p.size(); ++i) p.x[i] += 1e-6 * Vec3{u(rng), u(rng), 0.1 * u(rng)};
    }
    const std::vector<std::uint8_t> old_counts = ff.wall_counts();
    std::vector<std::vector<WallSlot>> old_slots(old_counts.size());
    for (std::size_t i = 0; i < old_counts.size(); ++i)
      for (int o = 0; o < old_counts[i]; ++o) old_slots[i].push_back(ff.wall_slot(i, o));
    ff.compute(p, nl, walls, dt);
    int contacts = 0, corners = 0, loaded = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      WallContact wc[ForceField::kWallSlots];
      const int found = walls[0].contacts(p.x[i], r, wc, ForceField::kWallSlots);
      Vec3 f{}, t{};
      REQUIRE(ff.wall_counts()[i] == found);
      for (int q = 0; q < found; ++q) {
        ContactHistory h{};
        for (int o = 0; o < (i < old_counts.size() ? old_counts[i] : 0); ++o) {
          const WallSlot& s = old_slots[i][o];
          if (s.wall == 0 && s.feature == wc[q].feature) h = s.history;
        }
        loaded += norm2(h.shear) > 0;
        const OneContact c = one_contact<ConstantTorqueRolling>(hm, roll, wc[q], walls[0].pose(), p.v[i], p.omega[i], r,
                                                                p.mass[i], p.inertia[i], h, dt);
        f += c.force;
        t += c.torque;
        const WallSlot& now = ff.wall_slot(i, q);
        CHECK(now.feature == wc[q].feature);
        CHECK(same_bits(now.history.shear, c.history.shear));
      }
      INFO("sphere id " << p.id[i] << ", " << found << " wall contacts");
      CHECK(same_bits(p.force[i], f));
      CHECK(same_bits(p.torque[i], t));
      contacts += found;
      corners += found == 3;
    }
    CHECK(contacts > 2 * WallBatch<ConstantTorqueRolling>::kCapacity);
    CHECK(corners == 4);
    if (step == 1) CHECK(loaded == contacts);
  }
}
