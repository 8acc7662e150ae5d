// The force loop evaluates touching pairs a PairBatch at a time, vectorised (dem/pair_batch.hpp).
// It must give exactly what one contact at a time gives: the same bits for forces, torques and
// histories, for every rolling model, in every branch of the models (sticking and sliding, fresh and
// loaded histories, spinning and still spheres). A compiler allowed to contract a*b+c into an FMA, or
// -ffast-math, would break this test.
#include <catch2/catch.hpp>

#include <cstring>
#include <random>

#include "dem/contact/rolling_constant_torque.hpp"
#include "dem/contact/rolling_epsd.hpp"
#include "dem/contact/rolling_none.hpp"
#include "dem/force_field.hpp"
#include "dem/neighbor_list.hpp"
#include "dem/pair_batch.hpp"
#include "dem/particles.hpp"

#include "batch_test_support.hpp"
#include "list_fixture.hpp"
#include "pressed_spheres_fixture.hpp"
#include "pass_one_loop.hpp"

using namespace grainscale::dem;
using grainscale::dem::testing::rolling_params;
using grainscale::dem::testing::same_bits;
using grainscale::dem::testing::sliding;

namespace {

struct OneContact {
  Vec3 force, torque_i, torque_j;
  ContactHistory history;
};

/// The pair loop's arithmetic for one contact (as dem/force_field.cpp had it before batching), out
/// of line so that the compiler cannot vectorise it with the batch.
template <class Rolling>
[[gnu::noinline]] OneContact one_contact(const PairBatch<Rolling>& b, int k, double dt) {
  const Vec3 d{b.dx[k], b.dy[k], b.dz[k]};
  const double dist = std::sqrt(b.dist2[k]);
  ContactKinematics c;
  c.n = (1.0 / dist) * d;
  c.overlap = b.rsum[k] - dist;
  c.lever_i = b.ri[k] - 0.5 * c.overlap;
  c.lever_j = b.rj[k] - 0.5 * c.overlap;
  c.omega_i = {b.wix[k], b.wiy[k], b.wiz[k]};
  c.omega_j = {b.wjx[k], b.wjy[k], b.wjz[k]};
  c.v_rel = Vec3{b.dvx[k], b.dvy[k], b.dvz[k]} - cross(c.lever_i * c.omega_i + c.lever_j * c.omega_j, c.n);
  c.r_eff = b.ri[k] * b.rj[k] / b.rsum[k];
  c.mass_i = b.mi[k];
  c.mass_j = b.mj[k];
  c.m_eff = c.mass_i * c.mass_j / (c.mass_i + c.mass_j);
  c.inertia_i = b.ii[k];
  c.inertia_j = b.ij[k];
  c.dt = dt;
  OneContact out;
  out.history = {{b.sx[k], b.sy[k], b.sz[k]}, {b.rx[k], b.ry[k], b.rz[k]}};
  const ContactForce f = HertzMindlin::evaluate(b.contact[k], c, out.history);
  Vec3 ti, tj;
  Rolling::evaluate(b.rolling[k], c, f, out.history, ti, tj);
  const Vec3 nxft = cross(c.n, f.tangential);
  out.force = f.force;
  out.torque_i = ti - c.lever_i * nxft;
  out.torque_j = tj - c.lever_j * nxft;
  return out;
}

}  // namespace

TEMPLATE_TEST_CASE("A vectorised batch of pair contacts gives one contact at a time's numbers bit for bit",
                   "[dem][contact]", NoRolling, ConstantTorqueRolling, EpsdRolling) {
  std::mt19937_64 rng(GENERATE(1u, 2u));
  std::uniform_real_distribution<double> u(-1, 1);
  const Material grain{"grain", 1380, 2.6e6, 0.3}, chaff{"chaff", 100, 1e6, 0.3};
  const PairProperties pp{0.5, 0.35, 0.08, true};
  const double dt = 2e-6;
  PairBatch<TestType> b;
  b.size = PairBatch<TestType>::kCapacity - 5;  // not a whole number of vector lanes
  for (int k = 0; k < b.size; ++k) {
    const double ri = 0.002 * (1.5 + u(rng)), rj = 0.002 * (1.5 + u(rng));
    const Vec3 dir = Vec3{u(rng), u(rng), u(rng)};
    const Vec3 n = (1.0 / norm(dir)) * dir;
    const double dist = (ri + rj) * (1 - 0.02 * (1 + u(rng)));  // overlaps up to 4 %
    b.dx[k] = dist * n.x, b.dy[k] = dist * n.y, b.dz[k] = dist * n.z;
    b.dist2[k] = b.dx[k] * b.dx[k] + b.dy[k] * b.dy[k] + b.dz[k] * b.dz[k];
    b.rsum[k] = ri + rj, b.ri[k] = ri, b.rj[k] = rj;
    b.dvx[k] = 0.1 * u(rng), b.dvy[k] = 0.1 * u(rng), b.dvz[k] = 0.1 * u(rng);
    const bool still = k % 5 == 0;  // some spheres not turning at all (the rolling models' w = 0 case)
    const double spin = still ? 0.0 : 50.0;
    b.wix[k] = spin * u(rng), b.wiy[k] = spin * u(rng), b.wiz[k] = spin * u(rng);
    b.wjx[k] = spin * u(rng), b.wjy[k] = spin * u(rng), b.wjz[k] = spin * u(rng);
    b.mi[k] = 1e-5 * (1.5 + u(rng)), b.mj[k] = 1e-5 * (1.5 + u(rng));
    b.ii[k] = 1e-11 * (1.5 + u(rng)), b.ij[k] = 1e-11 * (1.5 + u(rng));
    b.contact[k] = HertzMindlin::make(grain, k % 3 ? grain : chaff, pp);
    b.rolling[k] = rolling_params<TestType>(pp);
    // Fresh contacts (zero history), small springs (sticking) and large ones (sliding).
    const double s = k % 4 == 0 ? 0.0 : (k % 4 == 1 ? 1e-7 : 1e-4);
    b.sx[k] = s * u(rng), b.sy[k] = s * u(rng), b.sz[k] = s * u(rng);
    const double m = k % 2 ? 0.0 : 1e-6;
    b.rx[k] = m * u(rng), b.ry[k] = m * u(rng), b.rz[k] = m * u(rng);
    b.owner[k] = b.entry[k] = static_cast<std::uint32_t>(k);
  }
  std::vector<OneContact> expected;
  for (int k = 0; k < b.size; ++k) expected.push_back(one_contact(b, k, dt));

  b.evaluate(dt);

  int slides = 0;
  for (int k = 0; k < b.size; ++k) {
    INFO("contact " << k);
    const OneContact& e = expected[k];
    CHECK(same_bits(Vec3{b.fx[k], b.fy[k], b.fz[k]}, e.force));
    CHECK(same_bits(Vec3{b.tix[k], b.tiy[k], b.tiz[k]}, e.torque_i));
    CHECK(same_bits(Vec3{b.tjx[k], b.tjy[k], b.tjz[k]}, e.torque_j));
    CHECK(same_bits(Vec3{b.sx[k], b.sy[k], b.sz[k]}, e.history.shear));
    CHECK(same_bits(Vec3{b.rx[k], b.ry[k], b.rz[k]}, e.history.rolling));
    slides += sliding(Vec3{b.fx[k], b.fy[k], b.fz[k]}, Vec3{b.dx[k], b.dy[k], b.dz[k]}, pp.friction);
  }
  INFO(slides << " of " << b.size << " contacts sliding");
  CHECK(slides > 3);  // the Coulomb branch is taken by some, not all
  CHECK(slides < b.size - 3);
}

TEST_CASE("A sphere with more contacts than a batch holds gets the one-at-a-time loop's force and torque bit for bit",
          "[dem][contact]") {
  // A big sphere with 150 small ones pressed onto it: its contacts span several batches, so its sums
  // stay open across flushes. Every sphere's force and torque must be what the loop gave before
  // batching: the owner's contacts in entry order, then the partner shares in reverse-range order.
  MaterialTable materials;
  const int m = materials.add({"grain", 1380, 2.6e6, 0.3});
  materials.set_pair(m, m, {0.5, 0.35, 0.08, true});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const double skin = 0.0005, dt = 1e-6;
  Particles p = grainscale::dem::testing::big_sphere_pressed(m, 150, rng);
  NeighborList nl;
  grainscale::dem::testing::build_list(nl, p, skin);
  for (std::uint32_t k = 0; k < nl.entries(); ++k) {  // loaded springs: some contacts slide
    nl.shear(k) = 1e-6 * Vec3{u(rng), u(rng), u(rng)};
  }
  const NeighborList before = nl;
  std::size_t most = 0;
  for (std::size_t i = 0; i < p.size(); ++i) most = std::max<std::size_t>(most, nl.end(i) - nl.begin(i));
  INFO("most entries owned by one sphere: " << most);
  REQUIRE(most > 2 * PairBatch<ConstantTorqueRolling>::kCapacity);

  // Pass 1 has two entry loops (entry by entry for beds in the caches; a chunk's distance tests, then
  // its contacts, for beds beyond): both must give these numbers.
  const bool chunked = GENERATE(false, true);
  INFO("pass 1's " << (chunked ? "chunked" : "entry-by-entry") << " loop");
  const std::vector<Wall> walls;
  auto compute = [&](ForceField& f, Particles& q, NeighborList& l, bool chunked_loop) {
    const grainscale::dem::testing::PassOneLoop loop(chunked_loop);
    f.compute(q, l, walls, dt);
  };
  ForceField ff;
  ff.setup(materials, walls, RollingSettings{});
  compute(ff, p, nl, chunked);

  // The loop as it was, one contact at a time.
  const HertzMindlin::Params hm = HertzMindlin::make(materials[m], materials[m], materials.pair(m, m));
  const ConstantTorqueRolling::Params roll = ConstantTorqueRolling::make(materials.pair(m, m));
  const std::size_t n = p.size();
  std::vector<Vec3> f(n), t(n), share_f(nl.entries()), share_t(nl.entries());
  std::vector<bool> touching(nl.entries());
  NeighborList ref = before;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t k = ref.begin(i); k < ref.end(i); ++k) {
      const std::uint32_t j = ref.partner(k);
      const Vec3 d = p.x[i] - p.x[j];
      const double rsum = p.radius[i] + p.radius[j];
      if (norm2(d) >= rsum * rsum) continue;
      PairBatch<ConstantTorqueRolling> one;
      one.size = 1;
      one.dx[0] = d.x, one.dy[0] = d.y, one.dz[0] = d.z, one.dist2[0] = norm2(d), one.rsum[0] = rsum;
      one.ri[0] = p.radius[i], one.rj[0] = p.radius[j];
      const Vec3 dv = p.v[i] - p.v[j];
      one.dvx[0] = dv.x, one.dvy[0] = dv.y, one.dvz[0] = dv.z;
      one.wix[0] = p.omega[i].x, one.wiy[0] = p.omega[i].y, one.wiz[0] = p.omega[i].z;
      one.wjx[0] = p.omega[j].x, one.wjy[0] = p.omega[j].y, one.wjz[0] = p.omega[j].z;
      one.mi[0] = p.mass[i], one.mj[0] = p.mass[j], one.ii[0] = p.inertia[i], one.ij[0] = p.inertia[j];
      one.contact[0] = hm, one.rolling[0] = roll;
      const ContactHistory& h = ref.history(k);
      one.sx[0] = h.shear.x, one.sy[0] = h.shear.y, one.sz[0] = h.shear.z;
      one.rx[0] = h.rolling.x, one.ry[0] = h.rolling.y, one.rz[0] = h.rolling.z;
      const OneContact c = one_contact(one, 0, dt);
      f[i] += c.force;
      t[i] += c.torque_i;
      share_f[ref.rev_position(k)] = c.force, share_t[ref.rev_position(k)] = c.torque_j;
      touching[ref.rev_position(k)] = true;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t r = ref.rev_begin(i); r < ref.rev_end(i); ++r) {
      if (!touching[r]) continue;
      f[i] -= share_f[r];
      t[i] += share_t[r];
    }
  }
  int contacts = 0;
  for (std::size_t i = 0; i < n; ++i) {
    INFO("sphere id " << p.id[i]);
    CHECK(same_bits(p.force[i], f[i]));
    CHECK(same_bits(p.torque[i], t[i]));
  }
  for (std::size_t r = 0; r < touching.size(); ++r) contacts += touching[r];
  CHECK(contacts > 2 * PairBatch<ConstantTorqueRolling>::kCapacity);

  // And the same histories as the other loop: updated where touching, cleared where a loaded spring's
  // pair is apart (contact broken), over two steps (the second starts from the flags the first left).
  Particles q = p;
  NeighborList other = before;
  ForceField ff_other;
  ff_other.setup(materials, walls, RollingSettings{});
  compute(ff_other, q, other, !chunked);
  int cleared = 0;
  for (int step = 0; step < 2; ++step) {
    if (step == 1) {
      for (std::size_t i = 0; i < n; ++i) p.x[i] += dt * p.v[i], q.x[i] += dt * q.v[i];
      compute(ff, p, nl, chunked);
      compute(ff_other, q, other, !chunked);
    }
    for (std::uint32_t k = 0; k < nl.entries(); ++k) {
      INFO("step " << step << ", entry " << k);
      CHECK(same_bits(nl.history(k).shear, other.history(k).shear));
      CHECK(same_bits(nl.history(k).rolling, other.history(k).rolling));
      if (step == 0) cleared += norm2(before.history(k).shear) != 0 && norm2(nl.history(k).shear) == 0;
    }
    for (std::size_t i = 0; i < n; ++i) {
      CHECK(same_bits(p.force[i], q.force[i]));
      CHECK(same_bits(p.torque[i], q.torque[i]));
    }
  }
  INFO(cleared << " loaded springs of pairs apart cleared");
  CHECK(cleared > 0);
}
