// Coarse-grained fields of particle sets whose continuum fields are known exactly: a uniform
// lattice (density, volume fraction), rigid motions (velocity, zero shear rate), simple shear (the
// imposed shear rate), a two-layer mixture (a concentration step smeared by the kernel only),
// velocity fluctuations (temperature), a flat bed (its surface height).
#include <omp.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "coarsegrain/fields.hpp"
#include "coarsegrain/moments.hpp"
#include "coarsegrain/phase_average.hpp"
#include "lattice_fixture.hpp"

using namespace grainscale;
using namespace grainscale::cg;
using test::Lattice;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

Fields fields_of(const dem::Snapshot& snap, const Grid& grid, const Kernel& kernel, const std::vector<std::string>& chaff = {},
                 const ContainerPose& pose = {}) {
  const SpeciesTable species = species_from_snapshot(snap, chaff);
  const CgParticles p = container_particles(snap, pose, species);
  return derive_fields(coarse_grain(p, species.size(), grid, kernel), grid, species);
}

template <class F>
void for_each_cell(const Grid& g, F f) {
  for (int k = 0; k < g.cells[2]; ++k)
    for (int j = 0; j < g.cells[1]; ++j)
      for (int i = 0; i < g.cells[0]; ++i) f(std::array<int, 3>{i, j, k}, g.index(i, j, k));
}

Vec3 centre(const Grid& g, std::array<int, 3> ijk) { return {g.centre(0, ijk[0]), g.centre(1, ijk[1]), g.centre(2, ijk[2])}; }

}  // namespace

TEST_CASE("A uniform lattice gives its exact density and volume fraction away from walls", "[cg][fields]") {
  const KernelType type = GENERATE(KernelType::gaussian, KernelType::lucy);
  const Boundary boundary = GENERATE(Boundary::reflect, Boundary::renormalise);
  const int dimension = GENERATE(1, 2, 3);
  CAPTURE(name(type), name(boundary), dimension);
  const Grid grid = Lattice::grid(dimension);
  // Any width gives the exact values (each cell spans whole lattice periods); a narrow one leaves
  // more cells out of the walls' reach.
  const Kernel kernel{type, 0.5 * Lattice::a, boundary};
  const Fields f = fields_of(Lattice::snapshot([](const Vec3&) { return Vec3{}; }), grid, kernel);
  int checked = 0;
  for_each_cell(grid, [&](std::array<int, 3> ijk, std::size_t c) {
    // Reflection continues the lattice through the walls (the walls are lattice mid-planes), so it is
    // exact everywhere; renormalisation is exact only where the kernel does not reach a wall.
    // A cell more than two cut-offs from the walls gets nothing from particles whose kernels reach one.
    if (boundary == Boundary::renormalise && !Lattice::away_from_walls(grid, ijk, 2 * kernel.cutoff())) return;
    ++checked;
    CHECK_THAT(f.mixture.density[c], WithinRel(Lattice::density(), 1e-12));
    CHECK_THAT(f.mixture.volume_fraction[c], WithinRel(Lattice::volume_fraction(), 1e-12));
    CHECK_THAT(f.mixture.number_density[c], WithinRel(1 / std::pow(Lattice::a, 3), 1e-12));
  });
  CHECK(checked > 0);
}

TEST_CASE("Rigid translation: the velocity everywhere, zero shear rate and temperature", "[cg][fields]") {
  const KernelType type = GENERATE(KernelType::gaussian, KernelType::lucy);
  const int dimension = GENERATE(1, 2, 3);
  const Vec3 V{0.03, -0.01, 0.02};
  const Grid grid = Lattice::grid(dimension);
  const Fields f = fields_of(Lattice::snapshot([&](const Vec3&) { return V; }), grid, {type, Lattice::a, Boundary::reflect});
  for (std::size_t c = 0; c < grid.size(); ++c) {
    CHECK_THAT(f.mixture.velocity[c].x, WithinRel(V.x, 1e-13));
    CHECK_THAT(f.mixture.velocity[c].z, WithinRel(V.z, 1e-13));
    CHECK_THAT(f.shear_rate[c], WithinAbs(0, 1e-13));
    CHECK_THAT(f.mixture.temperature[c], WithinAbs(0, 1e-28));
  }
}

TEST_CASE("Rigid rotation: velocity omega x r away from walls, zero shear rate", "[cg][fields]") {
  const KernelType type = GENERATE(KernelType::gaussian, KernelType::lucy);
  // A 2-D grid sees rotation in the x-z plane; a 3-D grid any rotation.
  const int dimension = GENERATE(2, 3);
  const Vec3 omega = dimension == 2 ? Vec3{0, 0.8, 0} : Vec3{0.3, 0.8, -0.5};
  const Vec3 axis_point{0.07, 0.02, 0.03};
  auto v = [&](const Vec3& x) { return cross(omega, x - axis_point); };
  const Grid grid = Lattice::grid(dimension);
  // Narrower than the lattice spacing: the fields are still exact, because each cell spans whole
  // periods of the lattice and is symmetric about its centre; narrow leaves more cells away from walls.
  const Kernel kernel{type, 0.5 * Lattice::a, Boundary::reflect};
  const Fields f = fields_of(Lattice::snapshot(v), grid, kernel);
  int checked = 0;
  for_each_cell(grid, [&](std::array<int, 3> ijk, std::size_t c) {
    // Finite differences reach one cell further than the kernel.
    if (!Lattice::away_from_walls(grid, ijk, kernel.cutoff() + grid.spacing(0))) return;
    ++checked;
    Vec3 x = centre(grid, ijk);
    if (dimension == 2) x.y = 0.5 * Lattice::hi.y;  // width average of the lattice
    const Vec3 want = v(x);
    CHECK_THAT(f.mixture.velocity[c].x, WithinAbs(want.x, 1e-14));
    CHECK_THAT(f.mixture.velocity[c].y, WithinAbs(want.y, 1e-14));
    CHECK_THAT(f.mixture.velocity[c].z, WithinAbs(want.z, 1e-14));
    CHECK_THAT(f.shear_rate[c], WithinAbs(0, 1e-11));
  });
  CHECK(checked > 0);
}

TEST_CASE("Simple shear u_x = G z gives shear rate G", "[cg][fields]") {
  const KernelType type = GENERATE(KernelType::gaussian, KernelType::lucy);
  const int dimension = GENERATE(2, 3);
  const double G = 2.5;  // 1/s
  const Grid grid = Lattice::grid(dimension);
  const Kernel kernel{type, 0.5 * Lattice::a, Boundary::reflect};
  const Fields f = fields_of(Lattice::snapshot([&](const Vec3& x) { return Vec3{G * x.z, 0, 0}; }), grid, kernel);
  int checked = 0;
  for_each_cell(grid, [&](std::array<int, 3> ijk, std::size_t c) {
    if (!Lattice::away_from_walls(grid, ijk, kernel.cutoff() + grid.spacing(2))) return;
    ++checked;
    CHECK_THAT(f.shear_rate[c], WithinRel(G, 1e-11));
    CHECK_THAT(f.velocity_gradient[c][2], WithinRel(G, 1e-11));  // d u_x / d z
    CHECK_THAT(f.mixture.velocity[c].x, WithinRel(G * grid.centre(2, ijk[2]), 1e-12));
  });
  CHECK(checked > 0);
  // The definition itself: pure shear, pure rotation, dilation.
  CHECK_THAT(shear_rate({0, 0, G, 0, 0, 0, 0, 0, 0}), WithinRel(G, 1e-15));
  CHECK_THAT(shear_rate({0, 0, 1, 0, 0, 0, -1, 0, 0}), WithinAbs(0, 1e-15));
  CHECK_THAT(shear_rate({1, 0, 0, 0, 1, 0, 0, 0, 1}), WithinAbs(0, 1e-15));
}

TEST_CASE("A two-layer mixture gives a concentration step smeared by the kernel only", "[cg][fields]") {
  // Grain planes below z0, chaff planes above, spheres of one size. Reflection at floor and lid
  // continues the lattice (image planes), so the total is uniform and the chaff concentration in a
  // cell is the chaff planes' share of the cell integral of the kernel, with F the kernel's
  // distribution function (the Gaussian truncated at 3w):
  //     c = sum_{chaff planes and images} [F((b - z_k)/w) - F((a - z_k)/w)] / (h / a).
  // Nothing but the kernel spreads the step: c is exactly 0 and 1 beyond one cut-off from z0,
  // symmetric about z0, and its 10-90 % rise is the kernel's (2 x 1.2816 w for a Gaussian).
  const int nz = Lattice::nz;
  const double a = Lattice::a, z0 = 6 * a, H = nz * a;  // z0: mid-plane between the 6th and 7th planes
  dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
  for (int k = 0; k < nz; ++k)
    test::add_lattice(s, k < 6 ? 0 : 1, Lattice::r, Lattice::rho, {0.5 * a, 0.5 * a, (k + 0.5) * a}, a, Lattice::nx, 4, 1);
  const double w = 2 * a;
  const Grid grid = Grid::make(2, Lattice::lo, {Lattice::hi.x, 4 * a, H}, {20, 1, 24});  // h = a / 2 in z
  const Fields f = fields_of(s, grid, {KernelType::gaussian, w, Boundary::reflect}, {"chaff"});

  const double norm = std::erf(3 / std::sqrt(2.0)), Phi_m3 = 0.5 * std::erfc(3 / std::sqrt(2.0));
  auto F = [&](double t) { return t <= -3 ? 0.0 : t >= 3 ? 1.0 : (0.5 * std::erfc(-t / std::sqrt(2.0)) - Phi_m3) / norm; };
  const double h = grid.spacing(2);
  std::vector<double> c(static_cast<std::size_t>(grid.cells[2]));
  for (int k = 0; k < grid.cells[2]; ++k) {
    const double lo = grid.edge(2, k), hi = grid.edge(2, k + 1);
    double chaff = 0;
    for (int p = 6; p < nz; ++p) {
      const double zp = (p + 0.5) * a;
      for (double image : {zp, -zp, 2 * H - zp}) chaff += F((hi - image) / w) - F((lo - image) / w);
    }
    c[static_cast<std::size_t>(k)] = f.chaff_volume_concentration[grid.index(10, 0, k)];
    CAPTURE(k);
    CHECK_THAT(c[static_cast<std::size_t>(k)], WithinAbs(chaff * a / h, 1e-13));
    CHECK_THAT(f.chaff_number_concentration[grid.index(10, 0, k)], WithinAbs(chaff * a / h, 1e-13));
    if (hi <= z0 - 3 * w + 0.5 * a) CHECK(c[static_cast<std::size_t>(k)] == 0.0);
    if (lo >= z0 + 3 * w - 0.5 * a) CHECK_THAT(c[static_cast<std::size_t>(k)], WithinAbs(1.0, 1e-15));
  }
  for (int k = 0; k < 12; ++k) CHECK_THAT(c[static_cast<std::size_t>(k)] + c[static_cast<std::size_t>(23 - k)], WithinAbs(1.0, 1e-13));
  // 10 % and 90 % crossings by linear interpolation between cell centres.
  auto crossing = [&](double level) {
    for (int k = 0; k + 1 < grid.cells[2]; ++k) {
      const double c0 = c[static_cast<std::size_t>(k)], c1 = c[static_cast<std::size_t>(k) + 1];
      if (c0 < level && c1 >= level) return grid.centre(2, k) + (level - c0) / (c1 - c0) * h;
    }
    return std::nan("");
  };
  CHECK_THAT(crossing(0.9) - crossing(0.1), WithinRel(2 * 1.2816 * w, 0.03));
}

TEST_CASE("Granular temperature: the velocity fluctuation, within and between snapshots", "[cg][fields]") {
  const Grid grid = Lattice::grid(2);
  const Kernel kernel{KernelType::lucy, Lattice::a, Boundary::reflect};
  const double d = 0.04;
  // Alternating +d and -d along x on a checkerboard: zero mean velocity, T = d^2 / 3 (one component).
  auto checker = [&](const Vec3& x) {
    const long n = std::lround(x.x / Lattice::a - 0.5) + std::lround(x.y / Lattice::a - 0.5) + std::lround(x.z / Lattice::a - 0.5);
    return Vec3{n % 2 == 0 ? d : -d, 0, 0};
  };
  const dem::Snapshot s = Lattice::snapshot(checker);
  const Fields f = fields_of(s, grid, kernel);
  const std::size_t mid = grid.index(10, 0, 3);
  CHECK_THAT(f.mixture.velocity[mid].x, WithinAbs(0, 1e-16));
  CHECK_THAT(f.mixture.temperature[mid], WithinRel(d * d / 3, 1e-12));

  // Two snapshots of a bed moving rigidly at +V, then -V: each alone has T = 0; their window average
  // has mean velocity 0 and T = V^2 / 3; a phase average that puts them in different bins, T = 0.
  const Vec3 V{0.05, 0, 0};
  const SpeciesTable species = species_from_snapshot(s, {});
  auto moments = [&](const Vec3& vel, double t) {
    dem::Snapshot snap = Lattice::snapshot([&](const Vec3&) { return vel; });
    snap.time = t;
    return coarse_grain(container_particles(snap, {}, species), 1, grid, kernel);
  };
  const Moments forward = moments(V, 1.0), back = moments(-1.0 * V, 3.0);
  Moments window;
  window.add(forward);
  window.add(back);
  window.average();
  const Fields avg = derive_fields(window, grid, species);
  CHECK(avg.time == 2.0);
  CHECK(avg.snapshots == 1);
  CHECK_THAT(avg.mixture.velocity[mid].x, WithinAbs(0, 1e-16));
  CHECK_THAT(avg.mixture.temperature[mid], WithinRel(V.x * V.x / 3, 1e-12));
  CHECK_THAT(avg.mixture.density[mid], WithinRel(Lattice::density(), 1e-12));

  PhaseAverage phases(4);
  phases.add(0.1, forward);
  phases.add(2.6, back);   // phase 0.6 of the third cycle
  phases.add(1.12, forward);
  CHECK(phases.count(0) == 2);
  CHECK(phases.count(2) == 1);
  CHECK(phases.count(1) == 0);
  const Fields bin0 = derive_fields(phases.average(0), grid, species);
  CHECK_THAT(bin0.mixture.velocity[mid].x, WithinRel(V.x, 1e-13));
  CHECK_THAT(bin0.mixture.temperature[mid], WithinAbs(0, 1e-28));
  CHECK(phases.bin_of(-0.1) == 3);
  CHECK_THROWS(phases.bin_of(std::nan("")));
}

TEST_CASE("Free-surface height of a flat bed: the top lattice plane plus half a spacing", "[cg][fields]") {
  const KernelType type = GENERATE(KernelType::gaussian, KernelType::lucy);
  const int dimension = GENERATE(2, 3);
  // A bed of 8 planes in a box twice as high: the continuum bed ends at 8a, where the smeared volume
  // fraction falls to half. Cell edges lie on 8a, so the two cells either side are symmetric about it
  // and linear interpolation finds it exactly.
  dem::Snapshot s = test::empty_snapshot({"wheat"});
  test::add_lattice(s, 0, Lattice::r, Lattice::rho, {0.5 * Lattice::a, 0.5 * Lattice::a, 0.5 * Lattice::a}, Lattice::a,
                    Lattice::nx, Lattice::ny, 8);
  const Grid grid = Grid::make(dimension, Lattice::lo, {Lattice::hi.x, Lattice::hi.y, 16 * Lattice::a}, {20, 4, 16});
  const Fields f = fields_of(s, grid, {type, Lattice::a, Boundary::reflect});
  REQUIRE(f.surface_height.size() == static_cast<std::size_t>(grid.cells[0] * grid.cells[1]));
  for (double h : f.surface_height) CHECK_THAT(h, WithinAbs(8 * Lattice::a, 1e-12));
}

TEST_CASE("The same particles in a rotated and translated container give the same fields", "[cg][fields][frame]") {
  const dem::Snapshot in_box = Lattice::snapshot([](const Vec3& x) { return Vec3{0.1 * x.z, 0.02, -0.3 * x.x}; });
  ContainerPose pose;
  pose.origin = {1.5, -0.4, 0.9};
  pose.orientation = dem::normalized(dem::axis_angle(dem::Vec3{0.3, 1.0, 0.2} * (1.0 / std::sqrt(1.13)), 0.42));
  pose.velocity = {0.02, 0.0, -0.01};
  pose.angular_velocity = {0.0, 0.2, 0.05};
  dem::Snapshot in_world = in_box;
  for (std::size_t p = 0; p < in_world.position.size(); ++p) {
    in_world.velocity[p] = to_world_velocity(pose, in_box.position[p], in_box.velocity[p]);
    in_world.position[p] = to_world_position(pose, in_box.position[p]);
  }
  const Grid grid = Lattice::grid(3);
  const Kernel kernel{KernelType::gaussian, Lattice::a, Boundary::reflect};
  const Fields a = fields_of(in_box, grid, kernel), b = fields_of(in_world, grid, kernel, {}, pose);
  for (std::size_t c = 0; c < grid.size(); ++c) {
    CHECK_THAT(b.mixture.density[c], WithinRel(a.mixture.density[c], 1e-9));
    CHECK_THAT(b.mixture.velocity[c].x, WithinAbs(a.mixture.velocity[c].x, 1e-12));
    CHECK_THAT(b.mixture.velocity[c].z, WithinAbs(a.mixture.velocity[c].z, 1e-12));
    CHECK_THAT(b.shear_rate[c], WithinAbs(a.shear_rate[c], 1e-9));
  }
}

TEST_CASE("Moments are bitwise identical for one and two threads", "[cg][determinism]") {
  const dem::Snapshot s = Lattice::snapshot([](const Vec3& x) { return Vec3{std::sin(300 * x.x), x.z, std::cos(200 * x.y)}; });
  const SpeciesTable species = species_from_snapshot(s, {});
  const CgParticles p = container_particles(s, {}, species);
  const Grid grid = Lattice::grid(3);
  const Kernel kernel{KernelType::gaussian, 0.7 * Lattice::a, Boundary::reflect};
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  const Moments one = coarse_grain(p, 1, grid, kernel);
  omp_set_num_threads(2);
  const Moments two = coarse_grain(p, 1, grid, kernel);
  omp_set_num_threads(before);
  REQUIRE(one.mass.size() == two.mass.size());
  CHECK(std::memcmp(one.mass.data(), two.mass.data(), one.mass.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(one.fluctuation.data(), two.fluctuation.data(), one.mass.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(one.momentum.data(), two.momentum.data(), one.mass.size() * sizeof(Vec3)) == 0);
}
