// Throughput of the 2-D field set (issue 6: "particle-snapshots per second"). Hidden from the
// suite ([.] tag); run it by hand:  test_coarsegrain "[benchmark]"
#include <omp.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <iostream>
#include <random>

#include "coarsegrain/fields.hpp"
#include "coarsegrain/moments.hpp"
#include "synthetic_snapshot.hpp"

using namespace grainscale;
using namespace grainscale::cg;

TEST_CASE("Benchmark: particle-snapshots per second, 2-D field set", "[.][benchmark]") {
  // About the double-scale wheat bed: 80 000 spheres of 2 to 3.5 mm radius, 10 % chaff, in the
  // 0.8 x 0.2 m container up to 40 mm; 2-D grid of 2.5 mm cells; Gaussian of one 6.7 mm diameter.
  dem::Snapshot s = test::empty_snapshot({"wheat", "chaff"});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 80000;
  for (int k = 0; k < n; ++k) {
    const bool chaff = k % 10 == 0;
    test::add_sphere(s, chaff ? 1 : 0, 0.002 + 0.0015 * u(rng), chaff ? 100 : 1380, {0.8 * u(rng), 0.2 * u(rng), 0.04 * u(rng)},
                     {0.01 * (u(rng) - 0.5), 0, 0.01 * (u(rng) - 0.5)});
  }
  const SpeciesTable species = species_from_snapshot(s, {"chaff"});
  const Grid grid = Grid::make(2, {0, 0, 0}, {0.8, 0.2, 0.06}, {320, 1, 24});
  const Kernel kernel{KernelType::gaussian, 0.0067, Boundary::reflect};
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    const int repeats = 5;
    const auto t0 = std::chrono::steady_clock::now();
    double sink = 0;
    for (int r = 0; r < repeats; ++r) {
      const CgParticles p = container_particles(s, {}, species);
      const Fields f = derive_fields(coarse_grain(p, species.size(), grid, kernel), grid, species);
      sink += f.mixture.density[100];
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << threads << " thread(s): " << n * repeats / seconds << " particle-snapshots/s (" << seconds / repeats
              << " s per snapshot of " << n << " spheres; check " << sink << ")\n";
  }
}
