// STL, ASCII and binary (dem/triangle_mesh.hpp), and the mesh wall built from what it accepts.
#include "dem/input_error.hpp"
#include "dem/triangle_mesh.hpp"
#include "dem/walls/mesh.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed.stl");
  try {
    grainscale::dem::MeshGeometry wall(grainscale::dem::load_stl(path), 0, "fuzzed.stl");
    grainscale::dem::WallHit hits[8];
    (void)wall.nearby({0.1, 0.2, 0.3}, 0.5, hits, 8);
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
