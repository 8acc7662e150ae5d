#include "dem/snapshot.hpp"
#include "dem/walls/mesh.hpp"

#include <hdf5.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"
#include "grainscale_version.hpp"

namespace grainscale::dem {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------------
// HDF5 plumbing: quiet error stack, failures as exceptions, hid_t owners.

/// HDF5 prints its whole error stack to stderr by default; inside these functions every failure is
/// reported once, as an exception, so printing is switched off for the guard's lifetime and the
/// caller's setting restored afterwards.
class QuietHdf5 {
 public:
  QuietHdf5() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    H5Eclear2(H5E_DEFAULT);
  }
  ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietHdf5(const QuietHdf5&) = delete;
  QuietHdf5& operator=(const QuietHdf5&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// An HDF5 call failed. The public functions catch it and rethrow with the file path, as
/// std::runtime_error when writing and as InputError when reading.
class Hdf5Failure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Why the last HDF5 call failed: the outermost (API) message plus the innermost one, which is where
/// the operating system's reason ("No space left on device", "Permission denied") appears.
std::string hdf5_reason() {
  std::vector<std::string> messages;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* out) -> herr_t {
        if (e->desc != nullptr) static_cast<std::vector<std::string>*>(out)->emplace_back(e->desc);
        return 0;
      },
      &messages);
  H5Eclear2(H5E_DEFAULT);
  if (messages.empty()) return "unknown HDF5 error";
  if (messages.size() == 1) return messages.front();
  return messages.front() + " (" + messages.back() + ")";
}

[[noreturn]] void fail(const std::string& what) { throw Hdf5Failure(what + ": " + hdf5_reason()); }

void check(herr_t status, const std::string& what) {
  if (status < 0) fail(what);
}

/// Owner of one hid_t, closed with its matching H5?close when the owner goes out of scope, including
/// during stack unwinding; that is what keeps failures from leaking handles or an open file.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);

  Handle(hid_t id, Closer closer, const std::string& what) : id_(id), closer_(closer) {
    if (id_ < 0) fail(what);
  }
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, -1)), closer_(o.closer_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      release();
      id_ = std::exchange(o.id_, -1);
      closer_ = o.closer_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { release(); }

  hid_t id() const { return id_; }

  /// Close now and report failure (for a file, a failed close can mean lost data).
  void close(const std::string& what) {
    const hid_t id = std::exchange(id_, -1);
    if (id >= 0 && closer_(id) < 0) fail(what);
  }

 private:
  void release() noexcept {
    if (id_ >= 0) closer_(std::exchange(id_, -1));
  }

  hid_t id_;
  Closer closer_;
};

Handle property_list(hid_t cls, const std::string& what) { return {H5Pcreate(cls), H5Pclose, what}; }
Handle simple_space(std::initializer_list<hsize_t> dims) {
  const std::vector<hsize_t> d(dims);
  return {H5Screate_simple(static_cast<int>(d.size()), d.data(), nullptr), H5Sclose, "creating a dataspace"};
}
Handle scalar_space() { return {H5Screate(H5S_SCALAR), H5Sclose, "creating a dataspace"}; }

/// Variable-length UTF-8 strings: what h5py and h5dump show as plain text.
Handle string_type() {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose, "creating the string type");
  check(H5Tset_size(t.id(), H5T_VARIABLE), "creating the string type");
  check(H5Tset_cset(t.id(), H5T_CSET_UTF8), "creating the string type");
  return t;
}

/// File (explicit little-endian, so files are the same on every machine) and memory types.
template <class T>
struct H5Type;
template <>
struct H5Type<double> {
  static hid_t file() { return H5T_IEEE_F64LE; }
  static hid_t memory() { return H5T_NATIVE_DOUBLE; }
  static constexpr H5T_class_t kClass = H5T_FLOAT;
  static constexpr const char* kName = "float64";
};
template <>
struct H5Type<std::uint64_t> {
  static hid_t file() { return H5T_STD_U64LE; }
  static hid_t memory() { return H5T_NATIVE_UINT64; }
  static constexpr H5T_class_t kClass = H5T_INTEGER;
  static constexpr const char* kName = "uint64";
};
template <>
struct H5Type<std::int32_t> {
  static hid_t file() { return H5T_STD_I32LE; }
  static hid_t memory() { return H5T_NATIVE_INT32; }
  static constexpr H5T_class_t kClass = H5T_INTEGER;
  static constexpr const char* kName = "int32";
};

// ---------------------------------------------------------------------------------------------------
// Writing.

/// Creation properties shared by every object: no modification times, so that identical states give
/// byte-identical files (reproducibility checks can then compare files with cmp).
struct CreationProperties {
  Handle group = property_list(H5P_GROUP_CREATE, "creating group properties");
  Handle dataset = property_list(H5P_DATASET_CREATE, "creating dataset properties");
  CreationProperties() {
    check(H5Pset_obj_track_times(group.id(), false), "creating group properties");
    check(H5Pset_obj_track_times(dataset.id(), false), "creating dataset properties");
  }
};

Handle create_group(hid_t parent, const std::string& name, hid_t gcpl) {
  return {H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT), H5Gclose,
          "creating group '" + name + "'"};
}

void write_attribute(hid_t obj, const char* name, hid_t file_type, hid_t mem_type, hid_t space, const void* data) {
  const std::string what = std::string("writing attribute '") + name + "'";
  Handle a(H5Acreate2(obj, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, what);
  // An empty array (no materials) is a valid zero-length attribute with nothing to write.
  if (H5Sget_simple_extent_npoints(space) > 0) check(H5Awrite(a.id(), mem_type, data), what);
}

template <class T>
void write_scalar_attribute(hid_t obj, const char* name, T value) {
  write_attribute(obj, name, H5Type<T>::file(), H5Type<T>::memory(), scalar_space().id(), &value);
}

void write_vector_attribute(hid_t obj, const char* name, std::initializer_list<double> values) {
  const std::vector<double> v(values);
  write_attribute(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, simple_space({v.size()}).id(), v.data());
}

void write_string_attribute(hid_t obj, const char* name, const std::string& value) {
  const char* p = value.c_str();
  const Handle t = string_type();
  write_attribute(obj, name, t.id(), t.id(), scalar_space().id(), &p);
}

void write_string_array_attribute(hid_t obj, const char* name, const std::vector<std::string>& values) {
  std::vector<const char*> p;
  for (const std::string& s : values) p.push_back(s.c_str());
  const Handle t = string_type();
  write_attribute(obj, name, t.id(), t.id(), simple_space({values.size()}).id(), p.data());
}

/// One particle dataset of shape [rows] (cols == 0) or [rows x cols], contiguous and uncompressed so
/// that any reader (ParaView's XDMF reader included) can read it directly. rows == 0 is valid.
template <class T>
void write_dataset(hid_t group, const char* name, const std::vector<T>& data, hsize_t rows, hsize_t cols,
                   hid_t dcpl) {
  const std::string what = std::string("writing dataset '/particles/") + name + "'";
  const Handle space = cols == 0 ? simple_space({rows}) : simple_space({rows, cols});
  Handle d(H5Dcreate2(group, name, H5Type<T>::file(), space.id(), H5P_DEFAULT, dcpl, H5P_DEFAULT), H5Dclose, what);
  if (rows > 0) check(H5Dwrite(d.id(), H5Type<T>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), what);
}

/// Wall names become group names; reject the ones HDF5 would misread (a '/' makes a path) or that
/// would collide, before anything is written.
void check_wall_names(const std::vector<Wall>& walls, const std::string& path) {
  std::set<std::string> seen;
  for (const Wall& w : walls) {
    const std::string& n = w.name();
    if (n.empty() || n == "." || n.find('/') != std::string::npos) {
      throw std::runtime_error("cannot write snapshot '" + path + "': wall name '" + n +
                               "' cannot be an HDF5 group name (must be non-empty, not '.', without '/')");
    }
    if (!seen.insert(n).second) {
      throw std::runtime_error("cannot write snapshot '" + path + "': two walls are named '" + n +
                               "'; /walls/<name> needs unique names");
    }
  }
}

std::vector<double> flatten(const std::vector<Quat>& q) {
  std::vector<double> out(4 * q.size());
  for (std::size_t k = 0; k < q.size(); ++k) out[4 * k] = q[k].w, out[4 * k + 1] = q[k].x, out[4 * k + 2] = q[k].y, out[4 * k + 3] = q[k].z;
  return out;
}

std::vector<double> flatten(const std::vector<Vec3>& v) {
  std::vector<double> out(3 * v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[3 * k] = v[k].x, out[3 * k + 1] = v[k].y, out[3 * k + 2] = v[k].z;
  return out;
}

/// Bodies are renumbered with their spheres (dem/bodies.hpp); the file is in id order.
void write_bodies(hid_t file, const Bodies& b, const CreationProperties& props) {
  const std::size_t n = b.size();
  const std::vector<std::size_t> at = b.indices_by_id();
  auto gather = [&](const auto& field) {
    std::vector<std::decay_t<decltype(field[0])>> out(n);
    for (std::size_t k = 0; k < n; ++k) out[k] = field[at[k]];
    return out;
  };
  const Handle g = create_group(file, "bodies", props.group.id());
  const hid_t dcpl = props.dataset.id();
  write_dataset(g.id(), "id", gather(b.id), n, 0, dcpl);
  write_dataset(g.id(), "shape", gather(b.shape), n, 0, dcpl);
  write_dataset(g.id(), "mass", gather(b.mass), n, 0, dcpl);
  write_dataset(g.id(), "inertia", flatten(gather(b.inertia)), n, 3, dcpl);
  write_dataset(g.id(), "position", flatten(gather(b.x)), n, 3, dcpl);
  write_dataset(g.id(), "velocity", flatten(gather(b.v)), n, 3, dcpl);
  write_dataset(g.id(), "angular_velocity", flatten(gather(b.omega)), n, 3, dcpl);
  write_dataset(g.id(), "orientation", flatten(gather(b.q)), n, 4, dcpl);
}

void write_particles(hid_t file, const Particles& p, const Bodies& bodies, const CreationProperties& props) {
  // Slot order changes at every neighbour-list rebuild; the file is in id order.
  const std::size_t n = p.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });

  const Handle g = create_group(file, "particles", props.group.id());
  const hid_t dcpl = props.dataset.id();
  auto gather = [&](const auto& field) {
    std::vector<std::decay_t<decltype(field[0])>> out(n);
    for (std::size_t k = 0; k < n; ++k) out[k] = field[order[k]];
    return out;
  };
  auto gather3 = [&](const std::vector<Vec3>& field) {
    std::vector<double> out(3 * n);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3& a = field[order[k]];
      out[3 * k] = a.x, out[3 * k + 1] = a.y, out[3 * k + 2] = a.z;
    }
    return out;
  };
  write_dataset(g.id(), "id", gather(p.id), n, 0, dcpl);
  std::vector<std::uint64_t> body(n);
  for (std::size_t k = 0; k < n; ++k) body[k] = bodies.id[p.body[order[k]]];
  write_dataset(g.id(), "body", body, n, 0, dcpl);
  write_dataset(g.id(), "material", gather(p.material), n, 0, dcpl);
  write_dataset(g.id(), "radius", gather(p.radius), n, 0, dcpl);
  write_dataset(g.id(), "mass", gather(p.mass_share), n, 0, dcpl);
  write_dataset(g.id(), "position", gather3(p.x), n, 3, dcpl);
  write_dataset(g.id(), "velocity", gather3(p.v), n, 3, dcpl);
  write_dataset(g.id(), "angular_velocity", gather3(p.omega), n, 3, dcpl);
  std::vector<double> q(4 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const Quat& a = p.q[order[k]];
    q[4 * k] = a.w, q[4 * k + 1] = a.x, q[4 * k + 2] = a.y, q[4 * k + 3] = a.z;
  }
  write_dataset(g.id(), "orientation", q, n, 4, dcpl);
}

void write_walls(hid_t file, const std::vector<Wall>& walls, const CreationProperties& props) {
  // Track creation order so that a reader gets the walls back in the simulation's order rather than
  // alphabetically (h5py: track_order).
  Handle gcpl(H5Pcopy(props.group.id()), H5Pclose, "creating group properties");
  check(H5Pset_link_creation_order(gcpl.id(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED),
        "creating group properties");
  const Handle g = create_group(file, "walls", gcpl.id());
  for (const Wall& w : walls) {
    const Handle wg = create_group(g.id(), w.name(), props.group.id());
    const WallPose& pose = w.pose();
    write_vector_attribute(wg.id(), "origin", {pose.origin.x, pose.origin.y, pose.origin.z});
    write_vector_attribute(wg.id(), "orientation",
                           {pose.orientation.w, pose.orientation.x, pose.orientation.y, pose.orientation.z});
    write_vector_attribute(wg.id(), "velocity", {pose.velocity.x, pose.velocity.y, pose.velocity.z});
    write_vector_attribute(wg.id(), "angular_velocity",
                           {pose.angular_velocity.x, pose.angular_velocity.y, pose.angular_velocity.z});
    write_scalar_attribute<std::int32_t>(wg.id(), "moving", w.moving() ? 1 : 0);
    write_scalar_attribute<double>(wg.id(), "motion_phase", w.phase());
    // Mesh walls: the surface where it is now, so ParaView shows the container moving.
    if (const auto* mesh = dynamic_cast<const MeshGeometry*>(&w.geometry())) {
      const TriangleMesh& m = mesh->mesh();
      std::vector<double> xyz;
      xyz.reserve(3 * m.vertices.size());
      for (const Vec3& v : m.vertices) {
        const Vec3 x = pose.origin + rotate(pose.orientation, v);
        xyz.insert(xyz.end(), {x.x, x.y, x.z});
      }
      std::vector<std::int32_t> tri;
      tri.reserve(3 * m.triangles.size());
      for (const auto& t : m.triangles) tri.insert(tri.end(), {static_cast<std::int32_t>(t[0]), static_cast<std::int32_t>(t[1]), static_cast<std::int32_t>(t[2])});
      write_dataset(wg.id(), "vertices", xyz, m.vertices.size(), 3, props.dataset.id());
      write_dataset(wg.id(), "triangles", tri, m.triangles.size(), 3, props.dataset.id());
    }
  }
}

/// The complete snapshot file as bytes. HDF5 builds it in memory (core driver, no backing store) and
/// never touches the disk: HDF5 1.10 cannot recover from an I/O error while closing a file (the id
/// stays half-closed and H5close crashes at exit), so a full disk must surface in plain POSIX writes
/// of the finished image instead. The price is one extra copy of the file in memory while writing.
std::string snapshot_image(const Simulation& sim, const SnapshotInfo& info) {
  const CreationProperties props;
  // The root group's creation properties come from the file creation list.
  Handle fcpl = property_list(H5P_FILE_CREATE, "creating file properties");
  check(H5Pset_obj_track_times(fcpl.id(), false), "creating file properties");
  Handle fapl = property_list(H5P_FILE_ACCESS, "creating file access properties");
  // Grow the in-memory file in steps of about its final size (~132 bytes per particle).
  const std::size_t estimate = 65536 + 160 * sim.particles().size();
  check(H5Pset_fapl_core(fapl.id(), estimate, false), "creating file access properties");

  // The name only identifies the in-memory file (nothing is created under it); it is unique so that
  // two snapshots being built at once are not mistaken for one file opened twice.
  static std::atomic<unsigned long> serial{0};
  const std::string name = "grainscale_snapshot_image_" + std::to_string(serial++);
  Handle file(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, fcpl.id(), fapl.id()), H5Fclose, "creating the in-memory file");
  const hid_t f = file.id();
  std::vector<std::string> names;
  for (int m = 0; m < sim.materials().size(); ++m) names.push_back(sim.materials()[m].name);
  write_scalar_attribute<std::int32_t>(f, "layout_version", kSnapshotLayoutVersion);
  write_scalar_attribute<double>(f, "time", sim.time());
  write_scalar_attribute<std::uint64_t>(f, "step", sim.steps());
  write_scalar_attribute<double>(f, "scale_factor", sim.settings().scale_factor);
  write_string_attribute(f, "units", kSnapshotUnits);
  write_string_attribute(f, "code_version", std::string(grainscale::version) + " " + grainscale::git_revision);
  write_string_attribute(f, "scenario", info.scenario_name);
  write_scalar_attribute<std::uint64_t>(f, "seed", info.seed);
  write_string_array_attribute(f, "material_names", names);
  write_string_array_attribute(f, "shape_names", sim.shape_names());
  write_particles(f, sim.particles(), sim.bodies(), props);
  write_bodies(f, sim.bodies(), props);
  write_walls(f, sim.walls(), props);

  check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flushing the in-memory file");
  const ssize_t size = H5Fget_file_image(f, nullptr, 0);
  if (size < 0) fail("getting the file image");
  std::string image(static_cast<std::size_t>(size), '\0');
  if (H5Fget_file_image(f, image.data(), image.size()) != size) fail("getting the file image");
  file.close("closing the in-memory file");
  return image;
}

// ---------------------------------------------------------------------------------------------------
// Reading. Every problem is an InputError naming the file and the object.

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}
  const std::string& path() const { return path_; }

  [[noreturn]] void bad(const std::string& what) const {
    throw InputError("snapshot '" + path_ + "': " + what);
  }

  Handle open_file() const {
    std::error_code ec;
    if (!fs::exists(path_, ec)) bad("file does not exist");
    if (fs::is_directory(path_, ec)) bad("is a directory, expected an HDF5 snapshot file");
    const htri_t is_h5 = H5Fis_hdf5(path_.c_str());
    if (is_h5 == 0) bad("not an HDF5 file (expected an HDF5 snapshot written by grainscale)");
    if (is_h5 < 0) bad("cannot be opened: " + hdf5_reason());
    Handle f(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "opening the file");
    check_layout_version(f.id());
    return f;
  }

  Handle open_group(hid_t file, const char* name) const {
    if (H5Lexists(file, name, H5P_DEFAULT) <= 0) bad(std::string("lacks the group '/") + name + "'");
    return {H5Gopen2(file, name, H5P_DEFAULT), H5Gclose, std::string("opening group '/") + name + "'"};
  }

  Handle open_attribute(hid_t obj, const std::string& obj_path, const char* name, const std::string& expected) const {
    if (H5Aexists(obj, name) <= 0) {
      bad("lacks attribute '" + std::string(name) + "' on '" + obj_path + "' (expected " + expected + ")");
    }
    return {H5Aopen(obj, name, H5P_DEFAULT), H5Aclose, "opening attribute '" + std::string(name) + "'"};
  }

  /// Numeric attribute with exactly `n` elements (n == 1: scalar or one-element array).
  template <class T>
  std::vector<T> numeric_attribute(hid_t obj, const std::string& obj_path, const char* name, hssize_t n,
                                   const std::string& expected) const {
    const std::string where = "attribute '" + std::string(name) + "' on '" + obj_path + "'";
    const Handle a = open_attribute(obj, obj_path, name, expected);
    const Handle type(H5Aget_type(a.id()), H5Tclose, "reading " + where);
    const Handle space(H5Aget_space(a.id()), H5Sclose, "reading " + where);
    const hssize_t count = H5Sget_simple_extent_npoints(space.id());
    if (H5Tget_class(type.id()) != H5Type<T>::kClass || count != n) {
      bad(where + " has the wrong type or size (expected " + expected + ")");
    }
    std::vector<T> v(static_cast<std::size_t>(n));
    check(H5Aread(a.id(), H5Type<T>::memory(), v.data()), "reading " + where);
    return v;
  }

  template <class T>
  T scalar_attribute(hid_t obj, const char* name, const std::string& expected) const {
    return numeric_attribute<T>(obj, "/", name, 1, expected)[0];
  }

  /// String or string-array attribute, variable- or fixed-length (h5py writes either).
  std::vector<std::string> string_attribute(hid_t obj, const std::string& obj_path, const char* name,
                                            bool scalar) const {
    const std::string expected = scalar ? "a string" : "a 1-D array of strings";
    const std::string where = "attribute '" + std::string(name) + "' on '" + obj_path + "'";
    const Handle a = open_attribute(obj, obj_path, name, expected);
    const Handle file_type(H5Aget_type(a.id()), H5Tclose, "reading " + where);
    const Handle space(H5Aget_space(a.id()), H5Sclose, "reading " + where);
    const int rank = H5Sget_simple_extent_ndims(space.id());
    const hssize_t count = H5Sget_simple_extent_npoints(space.id());
    if (H5Tget_class(file_type.id()) != H5T_STRING || count < 0 || (scalar && count != 1) || (!scalar && rank != 1)) {
      bad(where + " has the wrong type or shape (expected " + expected + ")");
    }
    const std::size_t n = static_cast<std::size_t>(count);
    std::vector<std::string> out;
    if (n == 0) return out;
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose, "reading " + where);
    // HDF5 converts between string types of the same character set only (ASCII or UTF-8).
    check(H5Tset_cset(mem.id(), H5Tget_cset(file_type.id())), "reading " + where);
    if (H5Tis_variable_str(file_type.id()) > 0) {
      check(H5Tset_size(mem.id(), H5T_VARIABLE), "reading " + where);
      std::vector<char*> buf(n, nullptr);
      check(H5Aread(a.id(), mem.id(), buf.data()), "reading " + where);
      // The library allocated the strings; give them back even if copying them throws.
      struct Reclaim {
        hid_t type, space;
        std::vector<char*>& buf;
        ~Reclaim() { H5Dvlen_reclaim(type, space, H5P_DEFAULT, buf.data()); }
      } reclaim{mem.id(), space.id(), buf};
      for (const char* s : buf) out.emplace_back(s != nullptr ? s : "");
    } else {
      // One extra byte per string so that a NULLPAD/SPACEPAD string of full width keeps its last byte.
      const std::size_t width = H5Tget_size(file_type.id()) + 1;
      check(H5Tset_size(mem.id(), width), "reading " + where);
      check(H5Tset_strpad(mem.id(), H5T_STR_NULLTERM), "reading " + where);
      std::vector<char> buf(n * width, '\0');
      check(H5Aread(a.id(), mem.id(), buf.data()), "reading " + where);
      for (std::size_t i = 0; i < n; ++i) {
        const char* s = buf.data() + i * width;
        out.emplace_back(s, strnlen(s, width));
      }
    }
    return out;
  }

  /// Dataset /particles/<name> of shape [N] (cols == 0) or [N x cols]; sets or checks `rows` (N).
  template <class T>
  std::vector<T> dataset(hid_t group, const char* name, hsize_t cols, std::optional<hsize_t>& rows) const {
    const std::string where = std::string("dataset '/particles/") + name + "'";
    const std::string shape = cols == 0 ? "[N]" : "[N x " + std::to_string(cols) + "]";
    const std::string expected = std::string(H5Type<T>::kName) + " " + shape;
    if (H5Lexists(group, name, H5P_DEFAULT) <= 0) bad("lacks " + where + " (expected " + expected + ")");
    const Handle d(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose, "opening " + where);
    const Handle type(H5Dget_type(d.id()), H5Tclose, "reading " + where);
    const Handle space(H5Dget_space(d.id()), H5Sclose, "reading " + where);
    const int rank = H5Sget_simple_extent_ndims(space.id());
    hsize_t dims[2] = {0, 0};
    if (H5Tget_class(type.id()) != H5Type<T>::kClass) bad(where + " has the wrong type (expected " + expected + ")");
    if (rank != (cols == 0 ? 1 : 2) || H5Sget_simple_extent_dims(space.id(), dims, nullptr) < 0 ||
        (cols != 0 && dims[1] != cols)) {
      std::string got = "[";
      for (int i = 0; i < rank && i < 2; ++i) got += (i ? " x " : "") + std::to_string(dims[i]);
      bad(where + " has shape " + got + "], expected " + expected);
    }
    if (!rows) {
      rows = dims[0];
    } else if (dims[0] != *rows) {
      bad(where + " has " + std::to_string(dims[0]) + " rows but '/particles/id' has " + std::to_string(*rows) +
          " (all particle arrays must have the same length N)");
    }
    std::vector<T> v(dims[0] * std::max<hsize_t>(cols, 1));
    if (!v.empty()) {
      check(H5Dread(d.id(), H5Type<T>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "reading " + where);
    }
    return v;
  }

 private:
  void check_layout_version(hid_t file) const {
    const std::string expected = "int " + std::to_string(kSnapshotLayoutVersion);
    if (H5Aexists(file, "layout_version") <= 0) {
      bad("lacks the root attribute 'layout_version' (expected " + expected + "); not a grainscale snapshot?");
    }
    const int v = scalar_attribute<std::int32_t>(file, "layout_version", expected);
    if (v != kSnapshotLayoutVersion) {
      bad("root attribute 'layout_version' is " + std::to_string(v) + ", but this build reads only layout_version " +
          std::to_string(kSnapshotLayoutVersion) + " (docs/snapshot_layout.md)");
    }
  }

  std::string path_;
};

std::vector<Vec3> to_vec3(const std::vector<double>& a) {
  std::vector<Vec3> out(a.size() / 3);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = {a[3 * k], a[3 * k + 1], a[3 * k + 2]};
  return out;
}

/// Apply a permutation (new position k holds old element order[k]) to one array.
template <class T>
void reorder(std::vector<T>& a, const std::vector<std::size_t>& order) {
  std::vector<T> out(a.size());
  for (std::size_t k = 0; k < order.size(); ++k) out[k] = a[order[k]];
  a.swap(out);
}

void read_particles(const Reader& r, hid_t file, Snapshot& s) {
  const Handle g = r.open_group(file, "particles");
  std::optional<hsize_t> n;
  s.id = r.dataset<std::uint64_t>(g.id(), "id", 0, n);
  s.body = r.dataset<std::uint64_t>(g.id(), "body", 0, n);
  s.material = r.dataset<std::int32_t>(g.id(), "material", 0, n);
  s.radius = r.dataset<double>(g.id(), "radius", 0, n);
  s.mass = r.dataset<double>(g.id(), "mass", 0, n);
  s.position = to_vec3(r.dataset<double>(g.id(), "position", 3, n));
  s.velocity = to_vec3(r.dataset<double>(g.id(), "velocity", 3, n));
  s.angular_velocity = to_vec3(r.dataset<double>(g.id(), "angular_velocity", 3, n));
  const std::vector<double> q = r.dataset<double>(g.id(), "orientation", 4, n);
  s.orientation.resize(q.size() / 4);
  for (std::size_t k = 0; k < s.orientation.size(); ++k) {
    s.orientation[k] = {q[4 * k], q[4 * k + 1], q[4 * k + 2], q[4 * k + 3]};
  }

  for (std::int32_t m : s.material) {
    if (m < 0 || static_cast<std::size_t>(m) >= s.material_names.size()) {
      r.bad("dataset '/particles/material' holds index " + std::to_string(m) + ", but 'material_names' has " +
            std::to_string(s.material_names.size()) + " entries");
    }
  }
  // write_snapshot writes in id order; files from other writers are sorted here.
  if (!std::is_sorted(s.id.begin(), s.id.end())) {
    std::vector<std::size_t> order(s.id.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return s.id[a] < s.id[b]; });
    reorder(s.id, order), reorder(s.body, order), reorder(s.material, order), reorder(s.radius, order),
        reorder(s.mass, order);
    reorder(s.position, order), reorder(s.velocity, order), reorder(s.angular_velocity, order);
    reorder(s.orientation, order);
  }
  const auto dup = std::adjacent_find(s.id.begin(), s.id.end());
  if (dup != s.id.end()) r.bad("dataset '/particles/id' holds id " + std::to_string(*dup) + " twice");
}

void read_bodies(const Reader& r, hid_t file, Snapshot& s) {
  const Handle g = r.open_group(file, "bodies");
  std::optional<hsize_t> n;
  s.body_id = r.dataset<std::uint64_t>(g.id(), "id", 0, n);
  s.body_shape = r.dataset<std::int32_t>(g.id(), "shape", 0, n);
  s.body_mass = r.dataset<double>(g.id(), "mass", 0, n);
  s.body_inertia = to_vec3(r.dataset<double>(g.id(), "inertia", 3, n));
  s.body_position = to_vec3(r.dataset<double>(g.id(), "position", 3, n));
  s.body_velocity = to_vec3(r.dataset<double>(g.id(), "velocity", 3, n));
  s.body_angular_velocity = to_vec3(r.dataset<double>(g.id(), "angular_velocity", 3, n));
  const std::vector<double> q = r.dataset<double>(g.id(), "orientation", 4, n);
  s.body_orientation.resize(q.size() / 4);
  for (std::size_t k = 0; k < s.body_orientation.size(); ++k) {
    s.body_orientation[k] = {q[4 * k], q[4 * k + 1], q[4 * k + 2], q[4 * k + 3]};
  }
  if (!std::is_sorted(s.body_id.begin(), s.body_id.end()) ||
      std::adjacent_find(s.body_id.begin(), s.body_id.end()) != s.body_id.end()) {
    r.bad("dataset '/bodies/id' must hold distinct ids in ascending order");
  }
  for (std::int32_t k : s.body_shape) {
    if (k < -1 || k >= static_cast<std::int32_t>(s.shape_names.size())) {
      r.bad("dataset '/bodies/shape' holds index " + std::to_string(k) + ", but 'shape_names' has " +
            std::to_string(s.shape_names.size()) + " entries");
    }
  }
  for (std::uint64_t b : s.body) {
    if (!std::binary_search(s.body_id.begin(), s.body_id.end(), b)) {
      r.bad("dataset '/particles/body' refers to body " + std::to_string(b) + ", which '/bodies/id' lacks");
    }
  }
}

void read_walls(const Reader& r, hid_t file, Snapshot& s) {
  const Handle g = r.open_group(file, "walls");
  // Creation order where the writer tracked it (write_snapshot does), else name order.
  const Handle gcpl(H5Gget_create_plist(g.id()), H5Pclose, "reading group '/walls'");
  unsigned flags = 0;
  check(H5Pget_link_creation_order(gcpl.id(), &flags), "reading group '/walls'");
  const H5_index_t index = (flags & H5P_CRT_ORDER_INDEXED) ? H5_INDEX_CRT_ORDER : H5_INDEX_NAME;
  H5G_info_t info;
  check(H5Gget_info(g.id(), &info), "reading group '/walls'");
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len = H5Lget_name_by_idx(g.id(), ".", index, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) fail("reading group '/walls'");
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    if (H5Lget_name_by_idx(g.id(), ".", index, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT) < 0) {
      fail("reading group '/walls'");
    }
    name.resize(static_cast<std::size_t>(len));
    const std::string where = "/walls/" + name;
    const Handle wg(H5Gopen2(g.id(), name.c_str(), H5P_DEFAULT), H5Gclose, "opening group '" + where + "'");
    auto vec = [&](const char* attr) {
      const std::vector<double> v = r.numeric_attribute<double>(wg.id(), where, attr, 3, "float64[3]");
      return Vec3{v[0], v[1], v[2]};
    };
    WallPoseRecord w;
    w.name = name;
    w.origin = vec("origin");
    const std::vector<double> q =
        r.numeric_attribute<double>(wg.id(), where, "orientation", 4, "float64[4] (w, x, y, z)");
    w.orientation = {q[0], q[1], q[2], q[3]};
    w.velocity = vec("velocity");
    w.angular_velocity = vec("angular_velocity");
    // Added in the same layout version: absent in files from before motion existed.
    if (H5Aexists(wg.id(), "motion_phase") > 0) {
      w.motion_phase = r.numeric_attribute<double>(wg.id(), where, "motion_phase", 1, "float64")[0];
      w.moving = r.numeric_attribute<std::int32_t>(wg.id(), where, "moving", 1, "int32")[0] != 0;
    }
    s.walls.push_back(std::move(w));
  }
}

// ---------------------------------------------------------------------------------------------------
// XDMF.

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

/// Shortest text that reads back as exactly `t`.
std::string exact(double t) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, t);
  return std::string(buf, res.ptr);
}

void write_grid(std::ostream& o, double time, const std::string& ref, const std::string& name, hsize_t n) {
  const std::string N = std::to_string(n);
  auto item = [&](const std::string& dims, const char* type, int precision, const char* dataset) {
    o << "          <DataItem Dimensions=\"" << dims << "\" NumberType=\"" << type << "\" Precision=\"" << precision
      << "\" Format=\"HDF\">" << ref << ":/particles/" << dataset << "</DataItem>\n";
  };
  auto attribute = [&](const char* attr, const char* kind, const std::string& dims, const char* type, int precision) {
    o << "        <Attribute Name=\"" << attr << "\" AttributeType=\"" << kind << "\" Center=\"Node\">\n";
    item(dims, type, precision, attr);
    o << "        </Attribute>\n";
  };
  o << "      <Grid Name=\"" << name << "\" GridType=\"Uniform\">\n"
    << "        <Time Value=\"" << exact(time) << "\"/>\n"
    << "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << N << "\" NodesPerElement=\"1\"/>\n"
    << "        <Geometry GeometryType=\"XYZ\">\n";
  item(N + " 3", "Float", 8, "position");
  o << "        </Geometry>\n";
  attribute("radius", "Scalar", N, "Float", 8);
  attribute("material", "Scalar", N, "Int", 4);
  // XDMF 2 has no unsigned 64-bit type; ids are read as int64 (HDF5 converts, exact below 2^63).
  attribute("id", "Scalar", N, "Int", 8);
  attribute("velocity", "Vector", N + " 3", "Float", 8);
  attribute("angular_velocity", "Vector", N + " 3", "Float", 8);
  o << "      </Grid>\n";
}

}  // namespace

void write_snapshot(const Simulation& sim, const std::string& path, const SnapshotInfo& info) {
  check_wall_names(sim.walls(), path);
  try {
    std::string image;
    {
      const QuietHdf5 quiet;
      image = snapshot_image(sim, info);
    }
    write_file_atomically(path, image);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write snapshot '" + path + "': " + e.what());
  }
}

Snapshot read_snapshot(const std::string& path) {
  const QuietHdf5 quiet;
  const Reader r(path);
  try {
    const Handle f = r.open_file();
    const hid_t root = f.id();
    Snapshot s;
    s.layout_version = kSnapshotLayoutVersion;  // checked by open_file
    s.time = r.scalar_attribute<double>(root, "time", "float64 scalar, s");
    s.step = r.scalar_attribute<std::uint64_t>(root, "step", "uint64 scalar");
    s.scale_factor = r.scalar_attribute<double>(root, "scale_factor", "float64 scalar");
    s.units = r.string_attribute(root, "/", "units", true)[0];
    s.code_version = r.string_attribute(root, "/", "code_version", true)[0];
    s.scenario_name = r.string_attribute(root, "/", "scenario", true)[0];
    s.seed = r.scalar_attribute<std::uint64_t>(root, "seed", "uint64 scalar");
    s.material_names = r.string_attribute(root, "/", "material_names", false);
    s.shape_names = r.string_attribute(root, "/", "shape_names", false);
    read_particles(r, root, s);
    read_bodies(r, root, s);
    read_walls(r, root, s);
    return s;
  } catch (const Hdf5Failure& e) {
    r.bad(e.what());
  }
}

std::vector<XdmfMesh> xdmf_meshes(const Simulation& sim) {
  std::vector<XdmfMesh> out;
  for (const Wall& w : sim.walls()) {
    if (const auto* mesh = dynamic_cast<const MeshGeometry*>(&w.geometry())) {
      out.push_back({w.name(), mesh->mesh().vertices.size(), mesh->mesh().triangles.size()});
    }
  }
  return out;
}

void write_xdmf_series(const std::string& xmf_path, const std::vector<XdmfFrame>& frames) {
  const fs::path xmf_dir = fs::path(xmf_path).parent_path();
  std::ostringstream o;
  o << "<?xml version=\"1.0\" ?>\n"
    << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
    << "<!-- grainscale " << xml_escape(grainscale::version) << " " << xml_escape(grainscale::git_revision)
    << ": DEM snapshots as one time series (layout: docs/snapshot_layout.md) -->\n"
    << "<Xdmf Version=\"2.0\">\n"
    << "  <Domain>\n"
    << "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const XdmfFrame& f : frames) {
    if (!std::isfinite(f.time)) {
      throw std::invalid_argument("write_xdmf_series('" + xmf_path + "'): time of '" + f.h5 + "' is not finite");
    }
    const std::string ref = xml_escape(fs::path(f.h5).generic_string());
    if (!f.meshes.empty()) o << "      <Grid Name=\"frame\" GridType=\"Collection\" CollectionType=\"Spatial\">\n";
    write_grid(o, f.time, ref, xml_escape(fs::path(f.h5).stem().string()), static_cast<hsize_t>(f.particles));
    for (const XdmfMesh& m : f.meshes) {
      const std::string at = ref + ":/walls/" + xml_escape(m.name);
      o << "      <Grid Name=\"" << xml_escape(m.name) << "\" GridType=\"Uniform\">\n"
        << "        <Time Value=\"" << exact(f.time) << "\"/>\n"
        << "        <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << m.triangles << "\">\n"
        << "          <DataItem Dimensions=\"" << m.triangles << " 3\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">"
        << at << "/triangles</DataItem>\n"
        << "        </Topology>\n"
        << "        <Geometry GeometryType=\"XYZ\">\n"
        << "          <DataItem Dimensions=\"" << m.vertices << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
        << at << "/vertices</DataItem>\n"
        << "        </Geometry>\n"
        << "      </Grid>\n";
    }
    if (!f.meshes.empty()) o << "      </Grid>\n";
  }
  o << "    </Grid>\n"
    << "  </Domain>\n"
    << "</Xdmf>\n";
  try {
    write_file_atomically(xmf_path, o.str());
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write XDMF file '" + xmf_path + "': " + e.what());
  }
}

}  // namespace grainscale::dem
