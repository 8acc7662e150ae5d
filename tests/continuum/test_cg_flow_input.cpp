// The continuum model reads the coarse-graining stage's field file (docs/coarsegrain_layout.md)
// directly as its flow: u, shear rate and surface from one frame, empty columns dropped.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "hdf5_writer_fixture.hpp"
#include "continuum/gridded_flow.hpp"
#include "dem/input_error.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::continuum;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;

namespace {

using grainscale::testing::attribute;
using grainscale::testing::dataset;

/// A cg field file on a 2-D grid of nx x nz cells over [0, 0.8] x [0, 0.2]: a shear layer
/// u = g (z - h/2) with shear rate g below a flat surface h; the first column is empty (h NaN).
/// The granular temperature is T = (n + 1)² 1e-4 (1 + z / h) m²/s² in frame n. The solid fraction is
/// 0.6, except the top cell below the surface: `top_phi`, where u has `jet` added (a fast, dilute
/// surface flow). Written as `dir`/cg_fields.h5, replacing an earlier one there.
std::string write_cg_file(const grainscale::testing::TempDir& dir, double g, double h, int frames, double jet = 0,
                          double top_phi = 0.6) {
  const std::string path = dir / "cg_fields.h5";
  const int nx = 16, nz = 10;
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  attribute(f, "cg_layout_version", 1);
  const hid_t grid = H5Gcreate2(f, "grid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  attribute(grid, "dimension", 2);
  std::vector<double> x(nx), z(nz);
  for (int j = 0; j < nx; ++j) x[j] = 0.8 * (j + 0.5) / nx;
  for (int k = 0; k < nz; ++k) z[k] = 0.2 * (k + 0.5) / nz;
  dataset(grid, "x", {static_cast<hsize_t>(nx)}, x);
  dataset(grid, "z", {static_cast<hsize_t>(nz)}, z);
  H5Gclose(grid);
  const hid_t fr = H5Gcreate2(f, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  attribute(fr, "count", frames);
  for (int n = 0; n < frames; ++n) {
    char name[16];
    std::snprintf(name, sizeof name, "%06d", n);
    const hid_t one = H5Gcreate2(fr, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t mix = H5Gcreate2(one, "mixture", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> vel(nz * nx * 3, 0.0), rate(nz * nx), temperature(nz * nx), surface(nx, h), phi(nz * nx);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < nx; ++j) {
        const bool empty = j == 0 || z[k] > h, top = !empty && (k + 1 == nz || z[k + 1] > h);
        vel[(k * nx + j) * 3] = empty ? nan : (n + 1) * g * (z[k] - h / 2) + (top ? jet : 0.0);
        phi[k * nx + j] = empty ? nan : top ? top_phi : 0.6;
        rate[k * nx + j] = empty ? nan : (n + 1) * g;
        temperature[k * nx + j] = empty ? nan : (n + 1) * (n + 1) * 1e-4 * (1 + z[k] / h);
      }
    surface[0] = nan;
    dataset(mix, "velocity", {static_cast<hsize_t>(nz), 1, static_cast<hsize_t>(nx), 3}, vel);
    dataset(one, "shear_rate", {static_cast<hsize_t>(nz), 1, static_cast<hsize_t>(nx)}, rate);
    dataset(mix, "temperature", {static_cast<hsize_t>(nz), 1, static_cast<hsize_t>(nx)}, temperature);
    dataset(mix, "volume_fraction", {static_cast<hsize_t>(nz), 1, static_cast<hsize_t>(nx)}, phi);
    dataset(one, "surface_height", {1, static_cast<hsize_t>(nx)}, surface);
    H5Gclose(mix);
    H5Gclose(one);
  }
  H5Gclose(fr);
  H5Fclose(f);
  return path;
}

}  // namespace

TEST_CASE("Mobility from the granular temperature: the rate is sqrt(T) / d, the flow unchanged", "[continuum][flow]") {
  const double g = 0.3, h = 0.1, d = 5e-3;
  const grainscale::testing::TempDir tmp;  // a fresh folder, removed at the end: parallel ctest processes cannot race
  const std::string path = write_cg_file(tmp, g, h, 2);
  const GriddedFlow by_shear = GriddedFlow::load(path, 0.8, 1);
  const GriddedFlow by_temperature = GriddedFlow::load(path, 0.8, 1, d);
  for (const double z : {0.03, 0.05}) {  // data levels (cell centres), so no interpolation between them
    CHECK_THAT(by_temperature.shear_rate(0.4, z, 0), WithinAbs(std::sqrt(4e-4 * (1 + z / h)) / d, 1e-9));
    CHECK_THAT(by_temperature.stream_function(0.4, z, 0), WithinAbs(by_shear.stream_function(0.4, z, 0), 1e-15));
  }
}

TEST_CASE("The volume flux keeps a dilute surface jet's return flow out of the dense bed", "[continuum][flow]") {
  // A bed at rest (phi 0.6) under a fast, dilute top cell (u = 0.1 m/s, phi 0.03): its velocity
  // integrates to a column flux, and the depth-mean correction (G1) spreads the return flow over
  // the whole bed. Weighted by the solid fraction the jet carries 0.03 / phi_mean of it, and so
  // does the return flow. With a uniform phi both are the same flow.
  const double h = 0.1;
  const grainscale::testing::TempDir tmp;
  const std::string jet = write_cg_file(tmp, 0.0, h, 1, 0.1, 0.03);
  const GriddedFlow by_velocity = GriddedFlow::load(jet, 0.8, 0), by_volume = GriddedFlow::load(jet, 0.8, 0, 0, true);
  auto interior_u = [](const GriddedFlow& f) { return (f.stream_function(0.4, 0.05, 0) - f.stream_function(0.4, 0.03, 0)) / 0.02; };
  const double phi_mean = (4 * 0.6 + 0.03) / 5;  // the five data levels below h (z = 0.01 ... 0.09)
  INFO("interior u: " << interior_u(by_velocity) << " by velocity, " << interior_u(by_volume) << " by volume flux");
  CHECK(interior_u(by_velocity) < -0.01);  // a return flow of about 0.1 x (cell / depth) through the resting bed
  CHECK(interior_u(by_volume) == Approx(interior_u(by_velocity) * 0.03 / phi_mean).epsilon(0.05));
  const std::string shear = write_cg_file(tmp, 0.3, h, 1);  // replaces the jet's file, already loaded
  const GriddedFlow a = GriddedFlow::load(shear, 0.8, 0), b = GriddedFlow::load(shear, 0.8, 0, 0, true);
  for (const double z : {0.01, 0.03, 0.05, 0.07}) CHECK_THAT(b.stream_function(0.4, z, 0), WithinAbs(a.stream_function(0.4, z, 0), 1e-15));
}

TEST_CASE("A coarse-grained field file is read as the flow: shear rate, surface, chosen frame", "[continuum][flow]") {
  const double g = 0.3, h = 0.1;
  const grainscale::testing::TempDir tmp;
  const std::string path = write_cg_file(tmp, g, h, 2);
  const GriddedFlow last = GriddedFlow::load(path, 0.8);  // default: the last frame (n = 1: rate 2 g)
  const GriddedFlow first = GriddedFlow::load(path, 0.8, 0);
  CHECK_THAT(first.shear_rate(0.4, 0.03, 0), WithinAbs(g, 1e-12));
  CHECK_THAT(last.shear_rate(0.4, 0.03, 0), WithinAbs(2 * g, 1e-12));
  CHECK_THAT(first.surface_height(0.4), WithinAbs(h, 1e-12));
  CHECK_THAT(first.surface_height(0.01), WithinAbs(h, 1e-12));  // the empty first column was dropped
  // The stream function vanishes on the floor and on the surface (G1).
  CHECK_THAT(first.stream_function(0.4, 0.0, 0), WithinAbs(0, 1e-12));
  CHECK_THAT(first.stream_function(0.4, h, 0), WithinAbs(0, 1e-9));
  REQUIRE_THROWS_WITH(GriddedFlow::load(path, 0.8, 5), Contains("frames 0 to 1"));
}
