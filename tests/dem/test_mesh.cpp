// Triangle-mesh walls (dem/walls/mesh.hpp), STL input and generated containers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>

#include "dem/container_meshes.hpp"
#include "dem/input_error.hpp"
#include "dem/simulation.hpp"
#include "dem/walls/box.hpp"
#include "dem/walls/mesh.hpp"
#include "dem/walls/plane.hpp"
#include "tests/temp_dir.hpp"

using namespace grainscale::dem;
using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;

namespace {

/// A floor [-0.1, 0.1]^2 at z = 0 cut into an irregular grid of triangles (diagonals alternate),
/// so that a rolling sphere crosses many shared edges and vertices.
TriangleMesh tiled_floor() {
  TriangleMesh m;
  const double xs[] = {-0.1, -0.061, -0.033, -0.004, 0.0, 0.017, 0.052, 0.1};
  const double ys[] = {-0.1, -0.02, 0.0, 0.013, 0.1};
  for (int i = 0; i + 1 < 8; ++i)
    for (int j = 0; j + 1 < 5; ++j) {
      const Vec3 a{xs[i], ys[j], 0}, b{xs[i + 1], ys[j], 0}, c{xs[i + 1], ys[j + 1], 0}, d{xs[i], ys[j + 1], 0};
      if ((i + j) % 2) m.add_triangle(a, b, c), m.add_triangle(a, c, d);
      else m.add_triangle(a, b, d), m.add_triangle(b, c, d);
    }
  m.weld(1e-12);
  return m;
}

MaterialTable ball_and_floor() {
  MaterialTable mt;
  mt.add({"ball", 2500, 1e8, 0.3});
  mt.add({"floor", 1190, 7.97e8, 0.38});
  mt.set_pair(0, 0, {0.5, 0.4, 0.02, true});
  mt.set_pair(0, 1, {0.5, 0.4, 0.02, true});
  return mt;
}

struct Track {
  std::vector<Vec3> x, f;
};

/// A sphere dropped with a sideways velocity and spin, bouncing then rolling across the floor.
Track roll_on(std::shared_ptr<const WallGeometry> floor) {
  Simulation sim(ball_and_floor(), SimulationSettings{});
  sim.add_sphere(0, 0.004, {-0.07, -0.03, 0.006}, {0.4, 0.15, 0}, {3, -2, 1});
  sim.add_wall("floor", std::move(floor), 1);
  sim.setup();
  Track t;
  for (int s = 0; s < 20000; ++s) {
    sim.step();
    t.x.push_back(sim.particles().x[0]);
    t.f.push_back(sim.particles().force[0]);
  }
  return t;
}

}  // namespace

TEST_CASE("A floor made of triangles pushes like an analytic plane, also across shared edges and vertices",
          "[dem][mesh]") {
  const auto mesh = std::make_shared<MeshGeometry>(tiled_floor());
  REQUIRE(mesh->patches() == 1);  // 56 coplanar triangles: one surface
  const Track on_mesh = roll_on(mesh);
  const Track on_plane = roll_on(std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}));
  double worst_x = 0, worst_f = 0, weight = 2500 * 4.0 / 3.0 * M_PI * std::pow(0.004, 3) * 9.81;
  for (std::size_t k = 0; k < on_mesh.x.size(); ++k) {
    worst_x = std::max(worst_x, norm(on_mesh.x[k] - on_plane.x[k]));
    worst_f = std::max(worst_f, norm(on_mesh.f[k] - on_plane.f[k]));
  }
  INFO("travelled " << norm(on_plane.x.back() - on_plane.x.front()) << " m");
  CHECK(norm(on_plane.x.back() - on_plane.x.front()) > 0.05);  // it did cross many triangles
  CHECK(worst_x < 1e-12);
  CHECK(worst_f < 1e-9 * weight);
}

TEST_CASE("Mesh box features match the analytic box: faces in corners, one contact per face", "[dem][mesh]") {
  const Vec3 lo{0, 0, 0}, hi{0.8, 0.2, 0.2};
  const std::array<bool, 6> open_top{true, true, true, true, true, false};
  const MeshGeometry mesh(box_mesh(lo, hi, open_top), 0.01);
  const BoxGeometry box(lo, hi, open_top);
  CHECK(mesh.patches() == 5);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 p{0.8 * u(rng), 0.2 * u(rng), 0.2 * u(rng)};
    WallHit hm[16], hb[16];
    const int nm = mesh.nearby(p, 0.01, hm, 16), nb = box.nearby(p, 0.01, hb, 16);
    REQUIRE(nm == nb);
    for (int a = 0; a < nb; ++a) {
      bool found = false;
      for (int b = 0; b < nm; ++b)
        found |= std::abs(hm[b].distance - hb[a].distance) < 1e-12 && norm(hm[b].normal - hb[a].normal) < 1e-12;
      INFO("point (" << p.x << ", " << p.y << ", " << p.z << ") box hit " << a << ": d " << hb[a].distance << " n ("
                     << hb[a].normal.x << ", " << hb[a].normal.y << ", " << hb[a].normal.z << ")");
      CHECK(found);
    }
  }
}

TEST_CASE("A sphere over a convex rim touches the rim edge once, not the faces beside it", "[dem][mesh]") {
  const MeshGeometry mesh(box_mesh({0, 0, 0}, {0.8, 0.2, 0.2}, {true, true, true, true, true, false}), 0.01);
  // Centre above and outside the top edge of the -y wall (a plate of zero thickness at y = 0).
  const Vec3 p{0.4, -0.002, 0.203};
  WallHit h[16];
  const int n = mesh.nearby(p, 0.005, h, 16);
  REQUIRE(n == 1);
  CHECK(h[0].feature >= static_cast<int>(mesh.patches()));  // an edge, not a face
  CHECK_THAT(h[0].distance, WithinAbs(std::hypot(0.002, 0.003), 1e-12));
  CHECK(norm(h[0].normal - (1 / std::hypot(0.002, 0.003)) * Vec3{0, -0.002, 0.003}) < 1e-12);
}

TEST_CASE("The triangle bins find exactly what a search over every triangle finds", "[dem][mesh]") {
  // Binned (fine cells) against a single cell holding every triangle (brute force), near a pipe.
  const double cell = GENERATE(0.002, 0.007, 0.03);
  const MeshGeometry binned(pipe_mesh(0.05, 0.3, 48), cell), brute(pipe_mesh(0.05, 0.3, 48), 10.0);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int touching = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3 p{0.06 * u(rng), 0.06 * u(rng), 0.15 + 0.17 * u(rng)};
    WallHit a[16], b[16];
    const int na = binned.nearby(p, 0.008, a, 16), nb = brute.nearby(p, 0.008, b, 16);
    REQUIRE(na == nb);
    touching += na > 0;
    auto by_feature = [](const WallHit& x, const WallHit& y) { return x.feature < y.feature; };
    std::sort(a, a + na, by_feature);
    std::sort(b, b + nb, by_feature);
    for (int m = 0; m < na; ++m) {
      CHECK(a[m].feature == b[m].feature);
      CHECK(a[m].distance == b[m].distance);
    }
  }
  CHECK(touching > 300);
}

TEST_CASE("A sphere's hint gives the same hits as a query without one, in its cell and after it leaves it",
          "[dem][mesh]") {
  // The hint holds the sphere's cell and that cell's record (dem/walls/mesh.hpp); each sphere walks
  // through the pipe's grid in steps of a fifth of a cell, so it queries the same cell several times
  // and crosses into others. Hits compared bit for bit. (A hint belongs to its geometry: it names a
  // cell, not the grid, so the force field keeps one per sphere and wall.)
  const double cell = GENERATE(0.002, 0.007);
  const MeshGeometry mesh(pipe_mesh(0.05, 0.3, 48), cell);
  REQUIRE(mesh.uses_hints());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int touching = 0, reused = 0, queries = 0;
  for (int sphere = 0; sphere < 100; ++sphere) {
    WallGeometry::Hint hint = WallGeometry::kNoHint;
    Vec3 p{0.052 * u(rng), 0.052 * u(rng), 0.15 + 0.17 * u(rng)};
    const Vec3 step = (0.2 * cell) * Vec3{u(rng), u(rng), u(rng)};
    for (int k = 0; k < 60; ++k, p += step) {
      WallHit a[16], b[16];
      const WallGeometry::Hint before = hint;
      const int na = mesh.nearby(p, 0.004, a, 16), nb = mesh.nearby(p, 0.004, b, 16, hint);
      ++queries;
      reused += hint == before;
      REQUIRE(na == nb);
      touching += na > 0;
      for (int m = 0; m < na; ++m) {
        CHECK(a[m].feature == b[m].feature);
        CHECK(std::memcmp(&a[m].distance, &b[m].distance, sizeof(double)) == 0);
        CHECK(std::memcmp(&a[m].normal, &b[m].normal, sizeof(Vec3)) == 0);
      }
    }
  }
  INFO(touching << " queries touching, " << reused << " of " << queries << " with the hint unchanged");
  CHECK(touching > 300);
  CHECK(reused > queries / 2);
  CHECK(reused < queries - 100);
}

TEST_CASE("Cells that hold the same triangles share one stored list", "[dem][mesh]") {
  // The platform box's container in 6.25 mm cells (0.8 m / 128; 129 x 33 x 33): ~140,000 cells, of
  // which every one near a wall holds some of its 10 triangles, but only a few distinct lists (one or
  // both floor triangles, a side's two, the corners' unions). One copy of each keeps a query to one
  // scattered record (dem/walls/mesh.hpp).
  const std::array<bool, 6> open_top{true, true, true, true, true, false};
  const MeshGeometry mesh(box_mesh({0, 0, 0}, {0.8, 0.2, 0.2}, open_top), 0.00625);
  INFO(mesh.describe() << "; " << mesh.bin_lists() << " distinct lists");
  CHECK(mesh.bin_lists() >= 6);   // the empty list and at least one per wall
  CHECK(mesh.bin_lists() <= 100);
  CHECK(mesh.cells() == 129 * 33 * 33);
  // The default grid is that one (1/128 of the largest extent).
  const MeshGeometry automatic(box_mesh({0, 0, 0}, {0.8, 0.2, 0.2}, open_top));
  CHECK(automatic.cells() == mesh.cells());
  CHECK(automatic.bin_lists() == mesh.bin_lists());
  // A pipe's 96 facets are all different planes: its lists are many more, and still found right
  // (the brute-force comparison above).
  CHECK(MeshGeometry(pipe_mesh(0.05, 0.3, 48), 0.002).bin_lists() > 100);
}

TEST_CASE("STL files: binary and ASCII read back what was written; bad files are clear errors", "[dem][mesh][input]") {
  const grainscale::testing::TempDir tmp;  // a fresh folder: a parallel ctest cannot race on the files
  const TriangleMesh box = box_mesh({0, 0, 0}, {0.8, 0.2, 0.2}, {true, true, true, true, true, false}, 2);
  const std::string bin = tmp / "box.stl";
  write_stl(box, bin);
  const TriangleMesh back = load_stl(bin);
  CHECK(back.triangles.size() == box.triangles.size());
  CHECK(back.vertices.size() == box.vertices.size());  // corners welded again
  CHECK(MeshGeometry(back).patches() == 6);            // 5 sides + the divider

  const std::string ascii = tmp / "tri.stl";
  std::ofstream(ascii) << "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 10 0 0\n"
                          "   vertex 0 10 0\n  endloop\n endfacet\nendsolid t\n";
  const TriangleMesh tri = load_stl(ascii, 0.001);  // mm -> m
  REQUIRE(tri.triangles.size() == 1);
  CHECK_THAT(tri.vertices[1].x, WithinAbs(0.01, 1e-15));

  auto fails = [&](const std::string& text, const std::string& message) {
    const std::string p = tmp / "bad.stl";
    std::ofstream(p, std::ios::binary) << text;
    REQUIRE_THROWS_WITH(load_stl(p), Contains(message));
  };
  fails("solid t\n vertex 0 0 zero\nendsolid\n", ":2: 'vertex' needs three finite numbers");
  fails("solid t\n vertex 0 0 0\n vertex 1 0 0\nendsolid\n", "ends inside a facet");
  fails("solid empty\nendsolid empty\n", "no triangles");
  fails(std::string(80, 'x') + std::string("\x05\x00\x00\x00", 4) + std::string(60, '\0'), "declares 5 triangles");
  fails("hello", "not an STL file");
  REQUIRE_THROWS_AS(load_stl("/nonexistent.stl"), grainscale::InputError);
  REQUIRE_THROWS_AS(load_stl(bin, -1.0), grainscale::InputError);
}
