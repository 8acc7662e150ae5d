#pragma once
// The readers take file paths, so each fuzz input is written to a file first: one per process, in a
// private temporary folder that also holds the valid files a fuzzed scenario may refer to
// (materials.yaml, shape.yaml, mesh.stl, motion.csv, continuum.yaml, fields.csv, coverage.csv, a
// snapshots/ folder), so that parsing goes past the first reference.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace grainscale::fuzz {

inline const std::filesystem::path& work_dir() {
  // Made once and never destroyed: the exit handler below, registered while it is made, runs after
  // the destructors of statics made later, and a path held by value would be gone by then (the
  // folder was left behind by every run, 13 of them per test suite).
  static const std::filesystem::path* const dir = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "grainscale_fuzz_XXXXXX").string();
    if (mkdtemp(tmpl.data()) == nullptr) std::abort();
    const std::filesystem::path d = tmpl;
    std::ofstream(d / "materials.yaml") << "materials:\n  grain: {density: 1000, shear_modulus: 1.0e6, poisson_ratio: 0.3}\n"
                                           "  wall: {density: 1000, shear_modulus: 1.0e8, poisson_ratio: 0.3}\n"
                                           "pairs:\n  grain-grain: {restitution: 0.5, friction: 0.5, rolling_friction: 0.1}\n"
                                           "  grain-wall: {restitution: 0.5, friction: 0.5, rolling_friction: 0.1}\n";
    std::ofstream(d / "shape.yaml") << "name: pair\nlength_unit: mm\nspheres:\n  - {center: [-0.5, 0, 0], radius: 1}\n"
                                       "  - {center: [0.5, 0, 0], radius: 1}\n";
    std::ofstream(d / "mesh.stl") << "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                                     "endloop\nendfacet\nendsolid t\n";
    std::ofstream(d / "motion.csv") << "t_s,roll_deg,pitch_deg,yaw_deg,surge_m,sway_m,heave_m\n0,0,0,0,0,0,0\n"
                                       "1,1,0,0,0.01,0,0\n2,0,0,0,0,0,0\n";
    // For the later stages' readers: continuum settings, measured data, a folder of snapshots.
    std::ofstream(d / "continuum.yaml") << "grid: {length: 0.8, nx: 8, nz: 4, depth: 0.1}\n"
                                           "flow: {type: cellular, amplitude: 5.0e-4, background_shear: 0.05}\n"
                                           "terms:\n  advection: {limiter: van_leer}\n  segregation: {S: 1.0e-3}\n"
                                           "initial: {type: layers, below: 0.04, above: 0.0, split: 0.5}\n"
                                           "time: {end: 10, outputs: 2}\noutput: {folder: out}\n";
    std::ofstream(d / "fields.csv") << "t_s,x_m,z_m,c\n5,0.1,0.05,0.01\n10,0.5,0.02,nan\n10,0.7,0.08,0.03\n";
    std::ofstream(d / "coverage.csv") << "t_s,x_m,coverage,sigma\n5,0.1,0.2,0.05\n10,0.7,0.4,0.05\n";
    std::filesystem::create_directory(d / "snapshots");
    std::ofstream(d / "snapshots" / "snap_000000.h5") << "";
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(work_dir(), ec);
    });
    return new std::filesystem::path(d);
  }();
  return *dir;
}

/// Write the fuzz input to `name` in the work folder and return its path.
inline std::string input_file(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::filesystem::path p = work_dir() / name;
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p.string();
}

}  // namespace grainscale::fuzz
