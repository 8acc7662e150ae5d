#pragma once
// HDF5 snapshots of a DEM run: the hand-over from the DEM stage to coarse-graining and to ParaView.
// The file layout is a contract documented in docs/snapshot_layout.md; change it only together with
// kSnapshotLayoutVersion and that document.
//
// Particles are written sorted by their permanent id, never in slot order: the simulation renumbers
// slots for cache locality, and two runs in the same physical state must produce the same file
// (byte for byte: HDF5 object time stamps are switched off for the same reason).
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dem/quaternion.hpp"
#include "dem/simulation.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

/// Version of the file layout written by write_snapshot and the only one read_snapshot accepts.
inline constexpr int kSnapshotLayoutVersion = 2;  // 2: /particles/body and /bodies (clumps)
/// Value of the root attribute `units`: every quantity in a snapshot is plain SI.
inline constexpr const char* kSnapshotUnits = "SI: m, kg, s, rad";

/// Run metadata that the Simulation itself does not know.
struct SnapshotInfo {
  std::string scenario_name;
  std::uint64_t seed = 0;
};

/// Write the current state of `sim` to `path` atomically: the file is built in memory, written to
/// `path + ".tmp"` and renamed onto `path` (dem/atomic_file.hpp). On any failure the tmp file is
/// removed and std::runtime_error is thrown naming the path and the reason (e.g. "No space left on
/// device", "Permission denied"); an existing file at `path` is then left untouched.
/// Wall names become HDF5 group names, so they must be non-empty, unique, without '/' and not ".".
void write_snapshot(const Simulation& sim, const std::string& path, const SnapshotInfo& info);

/// Pose of one wall at the time of the snapshot (see WallPose for the meaning of the fields).
struct WallPoseRecord {
  std::string name;
  Vec3 origin;
  Quat orientation;
  Vec3 velocity;
  Vec3 angular_velocity;
  bool moving = false;       // has a prescribed motion
  double motion_phase = 0;   // position in the motion cycle, [0, 1)
};

/// Contents of a snapshot file. Particle arrays all have the same length and are sorted by id
/// ascending; `material[i]` indexes `material_names`. Walls are in the order they were added to the
/// simulation.
struct Snapshot {
  double time = 0;
  std::uint64_t step = 0;
  double scale_factor = 1;
  std::string code_version, scenario_name, units;
  std::uint64_t seed = 0;
  int layout_version = 0;
  std::vector<std::string> material_names;

  std::vector<std::uint64_t> id;
  std::vector<std::uint64_t> body;  // id of the body each sphere belongs to
  std::vector<std::int32_t> material;
  std::vector<double> radius, mass;
  std::vector<Vec3> position, velocity, angular_velocity;
  std::vector<Quat> orientation;

  /// Rigid bodies (loose spheres and clumps), sorted by id; `body_shape` indexes `shape_names`, -1 for
  /// a loose sphere.
  std::vector<std::string> shape_names;
  std::vector<std::uint64_t> body_id;
  std::vector<std::int32_t> body_shape;
  std::vector<double> body_mass;
  std::vector<Vec3> body_inertia;  // principal moments
  std::vector<Vec3> body_position, body_velocity, body_angular_velocity;
  std::vector<Quat> body_orientation;  // principal frame -> world

  std::vector<WallPoseRecord> walls;
};

/// Read a snapshot written by write_snapshot. Throws grainscale::InputError, naming the file and the
/// dataset or attribute concerned, if the file is missing or not HDF5, has another layout_version,
/// lacks a dataset/attribute or has one of the wrong type or shape, has particle arrays of
/// inconsistent lengths, duplicate ids, or material indices outside material_names.
Snapshot read_snapshot(const std::string& path);

/// One snapshot in an XDMF series. `h5` is relative to the .xmf's directory (or absolute), like
/// every path in an .xmf: for out/snapshots.xmf pass "snapshots/snap_000001.h5". Keeping references
/// relative lets the output directory be moved as a whole. `particles` is the snapshot's particle
/// count, which XDMF needs for the array sizes (the caller knows it; the files are not reopened, so
/// rewriting the series after every snapshot of a long run stays cheap).
/// A mesh wall stored in a snapshot (/walls/<name>/vertices and /triangles).
struct XdmfMesh {
  std::string name;
  std::uint64_t vertices = 0, triangles = 0;
};

struct XdmfFrame {
  double time = 0;
  std::string h5;
  std::uint64_t particles = 0;
  std::vector<XdmfMesh> meshes;  // shown beside the particles, where they are at `time`
};

/// The mesh walls of `sim`, for XdmfFrame::meshes.
std::vector<XdmfMesh> xdmf_meshes(const Simulation& sim);

/// Write (atomically, tmp + rename) an XDMF 2 file that makes ParaView open the given snapshots as one
/// time series: a temporal collection of Polyvertex grids on /particles/position with the attributes
/// radius, material, id, velocity and angular_velocity. std::runtime_error if the .xmf cannot be
/// written; std::invalid_argument for a non-finite time.
void write_xdmf_series(const std::string& xmf_path, const std::vector<XdmfFrame>& frames);

}  // namespace grainscale::dem
