// The model's initial chaff field from a coarse-grained DEM frame (continuum/initial_from_fields.hpp):
// averaged over y, nearest column with bed, nearest bed cell in it; cells above the bed are not used.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "hdf5_writer_fixture.hpp"
#include "continuum/grid.hpp"
#include "continuum/initial_from_fields.hpp"
#include "continuum/settings.hpp"
#include "dem/input_error.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::continuum;
using Catch::Matchers::Contains;

namespace {

using grainscale::testing::attribute;
using grainscale::testing::dataset;

// Cells of 20 x 2 x 10 mm: x_j = 0.01 + 0.02 j (10 columns), two y cells, z_k = 0.005 + 0.01 k
// (5 layers). c = 0.1 + x + 2 z, +-0.02 in the two y cells; the bed (phi 0.6) fills the lower
// three layers, above it phi = 0.05 (a few grains: not bed); column 3 holds no particles.
double truth(int j, int k) { return 0.1 + (0.01 + 0.02 * j) + 2 * (0.005 + 0.01 * k); }

std::string write_frame_file(const grainscale::testing::TempDir& dir) {
  const std::string path = dir / "initial_fields.h5";
  const int nx = 10, ny = 2, nz = 5;
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  attribute(f, "cg_layout_version", 1);
  const hid_t grid = H5Gcreate2(f, "grid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  attribute(grid, "dimension", 2);
  std::vector<double> x(nx), y(ny, 0.01), z(nz);
  for (int j = 0; j < nx; ++j) x[j] = 0.01 + 0.02 * j;
  for (int k = 0; k < nz; ++k) z[k] = 0.005 + 0.01 * k;
  dataset(grid, "x", {nx}, x);
  dataset(grid, "y", {ny}, y);
  dataset(grid, "z", {nz}, z);
  H5Gclose(grid);
  const hid_t frames = H5Gcreate2(f, "frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  attribute(frames, "count", 1);
  const hid_t one = H5Gcreate2(frames, "000000", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  attribute(one, "time", 2.95);
  const hid_t mix = H5Gcreate2(one, "mixture", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> c(nz * ny * nx), phi(nz * ny * nx);
  for (int k = 0; k < nz; ++k)
    for (int l = 0; l < ny; ++l)
      for (int j = 0; j < nx; ++j) {
        const std::size_t at = (static_cast<std::size_t>(k) * ny + l) * nx + j;
        c[at] = j == 3 ? nan : truth(j, k) + (l == 0 ? 0.02 : -0.02);
        phi[at] = j == 3 ? nan : k < 3 ? 0.6 : 0.05;
      }
  dataset(one, "chaff_volume_concentration", {nz, ny, nx}, c);
  dataset(mix, "volume_fraction", {nz, ny, nx}, phi);
  H5Gclose(mix);
  H5Gclose(one);
  H5Gclose(frames);
  H5Fclose(f);
  return path;
}

}  // namespace

TEST_CASE("The initial field comes from a coarse-grained frame: nearest bed cell, y-averaged", "[continuum][initial]") {
  // A fresh folder holds the frame file and the YAML beside it: a parallel ctest cannot race on them.
  const grainscale::testing::TempDir dir;
  const std::string path = write_frame_file(dir);
  // Model columns at x = 0.025, 0.075, 0.125, 0.175 m, layers at z = 5, 15, 25, 35 mm.
  const Grid g = Grid::flat(0.2, 0.04, 4, 4);
  const std::vector<double> c = initial_from_cg_frame(path, 0, 0.3, g);
  // Nearest columns: 0.03 (j = 1); 0.07 is empty, so 0.09 (j = 4, nearer than 0.05); 0.13; 0.17.
  const int column[4] = {1, 4, 6, 8};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) {
      CAPTURE(i, k);
      // The top layer (35 mm) lies in the cells above the bed: it takes the top bed cell (25 mm).
      CHECK(c[g.index(i, k)] == Approx(truth(column[i], std::min(k, 2))).margin(1e-12));
    }
  // The same frame counted from the end; a stricter bed threshold leaves nothing.
  CHECK(initial_from_cg_frame(path, -1, 0.3, g) == c);
  CHECK_THROWS_WITH(initial_from_cg_frame(path, 0, 0.7, g), Contains("no cell with solid fraction"));
  CHECK_THROWS_WITH(initial_from_cg_frame(path, 1, 0.3, g), Contains("initial.frame = 1") && Contains("frames 0 to 0"));

  // Through the model settings: `initial: {type: file, ...}`, the file beside the YAML.
  const std::string yaml = dir / "initial.yaml";
  std::ofstream(yaml) << "grid: {length: 0.2, nx: 4, nz: 4, depth: 0.04}\n"
                         "flow: {type: uniform_shear, shear_rate: 1.0}\n"
                         "terms: {segregation: {S: 1.0e-3}}\n"
                         "initial: {type: file, file: initial_fields.h5, frame: 0, min_solid_fraction: 0.3}\n"
                         "time: {end: 10}\n"
                         "output: {folder: out}\n";
  const ContinuumSettings s = load_continuum_settings(yaml);
  CHECK(initial_field(s, g) == c);
  std::ofstream(yaml) << "grid: {length: 0.2, nx: 4, nz: 4, depth: 0.04}\n"
                         "flow: {type: uniform_shear, shear_rate: 1.0}\n"
                         "terms: {segregation: {S: 1.0e-3}}\n"
                         "initial: {type: file, file: nowhere.h5}\n"
                         "time: {end: 10}\n"
                         "output: {folder: out}\n";
  CHECK_THROWS_WITH(load_continuum_settings(yaml), Contains("initial.file") && Contains("nowhere.h5"));
}
