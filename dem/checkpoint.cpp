#include "dem/checkpoint.hpp"

#include <hdf5.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "dem/atomic_file.hpp"
#include "dem/input_error.hpp"
#include "grainscale_version.hpp"

namespace grainscale::dem {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------------
// HDF5 plumbing. As for snapshots (dem/snapshot.cpp): failures become exceptions, HDF5's own printing
// is off meanwhile, every hid_t has an owner, and the file is built in memory and written with plain
// POSIX calls (HDF5 1.10 cannot recover from an I/O error while closing a file on disk).

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

class Hdf5Failure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The outermost and innermost messages of HDF5's error stack (the innermost carries the system's reason).
std::string hdf5_reason() {
  std::vector<std::string> m;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* out) -> herr_t {
        if (e->desc != nullptr) static_cast<std::vector<std::string>*>(out)->emplace_back(e->desc);
        return 0;
      },
      &m);
  H5Eclear2(H5E_DEFAULT);
  if (m.empty()) return "unknown HDF5 error";
  return m.size() == 1 ? m.front() : m.front() + " (" + m.back() + ")";
}

[[noreturn]] void fail(const std::string& what) { throw Hdf5Failure(what + ": " + hdf5_reason()); }
void check(herr_t status, const std::string& what) {
  if (status < 0) fail(what);
}

/// Owner of one hid_t.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer closer, const std::string& what) : id_(id), closer_(closer) {
    if (id_ < 0) fail(what);
  }
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, -1)), closer_(o.closer_) {}
  Handle& operator=(Handle&&) = delete;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }
  hid_t id() const { return id_; }
  void close(const std::string& what) {
    const hid_t id = std::exchange(id_, -1);
    if (id >= 0 && closer_(id) < 0) fail(what);
  }

 private:
  hid_t id_;
  Closer closer_;
};

Handle space(std::initializer_list<hsize_t> dims) {
  const std::vector<hsize_t> d(dims);
  return {H5Screate_simple(static_cast<int>(d.size()), d.data(), nullptr), H5Sclose, "creating a dataspace"};
}
Handle string_type() {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose, "creating the string type");
  check(H5Tset_size(t.id(), H5T_VARIABLE), "creating the string type");
  check(H5Tset_cset(t.id(), H5T_CSET_UTF8), "creating the string type");
  return t;
}

/// File (little-endian: the same bytes on every machine) and memory types of the scalars.
template <class T>
struct H5Type;
#define GRAINSCALE_H5TYPE(T, FILE_T, MEM_T, CLASS, NAME) \
  template <>                                             \
  struct H5Type<T> {                                      \
    static hid_t file() { return FILE_T; }                \
    static hid_t memory() { return MEM_T; }               \
    static constexpr H5T_class_t kClass = CLASS;          \
    static constexpr const char* kName = NAME;            \
  };
GRAINSCALE_H5TYPE(double, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, H5T_FLOAT, "float64")
GRAINSCALE_H5TYPE(std::uint64_t, H5T_STD_U64LE, H5T_NATIVE_UINT64, H5T_INTEGER, "uint64")
GRAINSCALE_H5TYPE(std::int64_t, H5T_STD_I64LE, H5T_NATIVE_INT64, H5T_INTEGER, "int64")
GRAINSCALE_H5TYPE(std::uint32_t, H5T_STD_U32LE, H5T_NATIVE_UINT32, H5T_INTEGER, "uint32")
GRAINSCALE_H5TYPE(std::int32_t, H5T_STD_I32LE, H5T_NATIVE_INT32, H5T_INTEGER, "int32")
GRAINSCALE_H5TYPE(std::uint8_t, H5T_STD_U8LE, H5T_NATIVE_UINT8, H5T_INTEGER, "uint8")
#undef GRAINSCALE_H5TYPE

/// How an array element is stored: a row of `kCols` scalars (kCols = 0: a 1-D dataset of scalars).
/// Vectors, quaternions and contact histories are plain structs of doubles, written and read in place.
template <class E>
struct Layout {
  using Scalar = E;
  static constexpr hsize_t kCols = 0;
};
template <>
struct Layout<Vec3> {
  using Scalar = double;
  static constexpr hsize_t kCols = 3;
};
template <>
struct Layout<Quat> {
  using Scalar = double;
  static constexpr hsize_t kCols = 4;
};
template <>
struct Layout<ContactHistory> {
  using Scalar = double;
  static constexpr hsize_t kCols = 6;
};
static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>);
static_assert(sizeof(Quat) == 4 * sizeof(double) && std::is_standard_layout_v<Quat>);
static_assert(sizeof(ContactHistory) == 6 * sizeof(double) && std::is_standard_layout_v<ContactHistory>);

// ---------------------------------------------------------------------------------------------------
// Writing: an in-memory HDF5 file, handed back as bytes.

class ImageWriter {
 public:
  explicit ImageWriter(std::size_t estimate) {
    // No object time stamps: the same state gives the same bytes.
    check(H5Pset_obj_track_times(fcpl_.id(), false), "creating file properties");
    check(H5Pset_obj_track_times(gcpl_.id(), false), "creating group properties");
    check(H5Pset_obj_track_times(dcpl_.id(), false), "creating dataset properties");
    check(H5Pset_fapl_core(fapl_.id(), estimate, false), "creating file access properties");
    static std::atomic<unsigned long> serial{0};  // names the in-memory file; nothing is created under it
    const std::string name = "grainscale_checkpoint_image_" + std::to_string(serial++);
    file_.emplace(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, fcpl_.id(), fapl_.id()), H5Fclose, "creating the in-memory file");
  }

  void group(const std::string& path) {
    Handle g(H5Gcreate2(file_->id(), path.c_str(), H5P_DEFAULT, gcpl_.id(), H5P_DEFAULT), H5Gclose,
             "creating group '" + path + "'");
  }

  template <class E>
  void dataset(const std::string& path, const std::vector<E>& v) {
    using S = typename Layout<E>::Scalar;
    const std::string what = "writing dataset '" + path + "'";
    const hsize_t rows = v.size(), cols = Layout<E>::kCols;
    const Handle sp = cols == 0 ? space({rows}) : space({rows, cols});
    Handle d(H5Dcreate2(file_->id(), path.c_str(), H5Type<S>::file(), sp.id(), H5P_DEFAULT, dcpl_.id(), H5P_DEFAULT),
             H5Dclose, what);
    if (rows > 0) check(H5Dwrite(d.id(), H5Type<S>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), what);
  }

  void strings(const std::string& path, const std::vector<std::string>& v) {
    const std::string what = "writing dataset '" + path + "'";
    std::vector<const char*> p;
    for (const std::string& s : v) p.push_back(s.c_str());
    const Handle t = string_type();
    const Handle sp = space({v.size()});
    Handle d(H5Dcreate2(file_->id(), path.c_str(), t.id(), sp.id(), H5P_DEFAULT, dcpl_.id(), H5P_DEFAULT), H5Dclose,
             what);
    if (!v.empty()) check(H5Dwrite(d.id(), t.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, p.data()), what);
  }

  template <class T>
  void attribute(const std::string& object, const char* name, T value) {
    write_attribute(object, name, H5Type<T>::file(), H5Type<T>::memory(), Handle(H5Screate(H5S_SCALAR), H5Sclose, "creating a dataspace").id(), &value);
  }
  void attribute(const std::string& object, const char* name, const std::string& value) {
    const char* p = value.c_str();
    const Handle t = string_type();
    write_attribute(object, name, t.id(), t.id(), Handle(H5Screate(H5S_SCALAR), H5Sclose, "creating a dataspace").id(), &p);
  }
  void attribute(const std::string& object, const char* name, const std::vector<std::string>& values) {
    std::vector<const char*> p;
    for (const std::string& s : values) p.push_back(s.c_str());
    const Handle t = string_type();
    write_attribute(object, name, t.id(), t.id(), space({values.size()}).id(), p.data());
  }

  std::string finish() {
    check(H5Fflush(file_->id(), H5F_SCOPE_GLOBAL), "flushing the in-memory file");
    const ssize_t size = H5Fget_file_image(file_->id(), nullptr, 0);
    if (size < 0) fail("getting the file image");
    std::string image(static_cast<std::size_t>(size), '\0');
    if (H5Fget_file_image(file_->id(), image.data(), image.size()) != size) fail("getting the file image");
    file_->close("closing the in-memory file");
    return image;
  }

 private:
  void write_attribute(const std::string& object, const char* name, hid_t file_type, hid_t mem_type, hid_t sp,
                       const void* data) {
    const std::string what = "writing attribute '" + std::string(name) + "' of '" + object + "'";
    Handle a(H5Acreate_by_name(file_->id(), object.c_str(), name, file_type, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             H5Aclose, what);
    if (H5Sget_simple_extent_npoints(sp) > 0) check(H5Awrite(a.id(), mem_type, data), what);
  }

  Handle fcpl_{H5Pcreate(H5P_FILE_CREATE), H5Pclose, "creating file properties"};
  Handle fapl_{H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "creating file access properties"};
  Handle gcpl_{H5Pcreate(H5P_GROUP_CREATE), H5Pclose, "creating group properties"};
  Handle dcpl_{H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "creating dataset properties"};
  std::optional<Handle> file_;
};

// ---------------------------------------------------------------------------------------------------
// Reading. Every problem is an InputError naming the file and the object.

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {
    std::error_code ec;
    if (!fs::exists(path_, ec)) bad("file does not exist");
    if (fs::is_directory(path_, ec)) bad("is a directory, expected an HDF5 checkpoint file");
    const htri_t is_h5 = H5Fis_hdf5(path_.c_str());
    if (is_h5 == 0) bad("not an HDF5 file (expected a checkpoint written by grainscale)");
    if (is_h5 < 0) bad("cannot be opened: " + hdf5_reason());
    file_.emplace(H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "opening the file");
  }

  [[noreturn]] void bad(const std::string& what) const { throw InputError("checkpoint '" + path_ + "': " + what); }

  bool has(const std::string& path) const { return H5Lexists(file_->id(), path.c_str(), H5P_DEFAULT) > 0; }
  bool has_attribute(const std::string& object, const char* name) const {
    return H5Aexists_by_name(file_->id(), object.c_str(), name, H5P_DEFAULT) > 0;
  }

  /// Dataset `path` of elements E: shape [rows] or [rows x Layout<E>::kCols]; `rows` given: checked.
  template <class E>
  std::vector<E> dataset(const std::string& path, std::optional<hsize_t> rows = std::nullopt) const {
    using S = typename Layout<E>::Scalar;
    const hsize_t cols = Layout<E>::kCols;
    const std::string expected = std::string(H5Type<S>::kName) + (cols == 0 ? " [N]" : " [N x " + std::to_string(cols) + "]");
    const std::string where = "dataset '" + path + "'";
    const Handle d = open_dataset(path, expected);
    const Handle type(H5Dget_type(d.id()), H5Tclose, "reading " + where);
    const Handle sp(H5Dget_space(d.id()), H5Sclose, "reading " + where);
    hsize_t dims[2] = {0, 0};
    const int rank = H5Sget_simple_extent_ndims(sp.id());
    if (H5Tget_class(type.id()) != H5Type<S>::kClass || H5Tget_size(type.id()) != sizeof(S) ||
        (H5Type<S>::kClass == H5T_INTEGER && H5Tget_sign(type.id()) != H5Tget_sign(H5Type<S>::memory()))) {
      bad(where + " has the wrong type (expected " + expected + ")");
    }
    if (rank != (cols == 0 ? 1 : 2) || H5Sget_simple_extent_dims(sp.id(), dims, nullptr) < 0 || (cols != 0 && dims[1] != cols)) {
      bad(where + " has the wrong shape (expected " + expected + ")");
    }
    if (rows && dims[0] != *rows) {
      bad(where + " has " + std::to_string(dims[0]) + " rows, expected " + std::to_string(*rows));
    }
    std::vector<E> v(dims[0]);
    if (!v.empty()) check(H5Dread(d.id(), H5Type<S>::memory(), H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "reading " + where);
    return v;
  }

  std::vector<std::string> strings(const std::string& path) const {
    const std::string where = "dataset '" + path + "'";
    const Handle d = open_dataset(path, "a 1-D array of strings");
    const Handle type(H5Dget_type(d.id()), H5Tclose, "reading " + where);
    const Handle sp(H5Dget_space(d.id()), H5Sclose, "reading " + where);
    if (H5Tget_class(type.id()) != H5T_STRING || H5Tis_variable_str(type.id()) <= 0 ||
        H5Sget_simple_extent_ndims(sp.id()) != 1) {
      bad(where + " has the wrong type or shape (expected a 1-D array of variable-length strings)");
    }
    return read_strings(sp.id(), [&](hid_t mem, void* buf) { return H5Dread(d.id(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); },
                        where);
  }

  template <class T>
  T attribute(const std::string& object, const char* name) const {
    const std::string where = "attribute '" + std::string(name) + "' of '" + object + "'";
    const Handle a = open_attribute(object, name, H5Type<T>::kName);
    const Handle type(H5Aget_type(a.id()), H5Tclose, "reading " + where);
    const Handle sp(H5Aget_space(a.id()), H5Sclose, "reading " + where);
    if (H5Tget_class(type.id()) != H5Type<T>::kClass || H5Sget_simple_extent_npoints(sp.id()) != 1) {
      bad(where + " has the wrong type or size (expected a " + H5Type<T>::kName + " scalar)");
    }
    T v{};
    check(H5Aread(a.id(), H5Type<T>::memory(), &v), "reading " + where);
    return v;
  }

  std::vector<std::string> string_attribute(const std::string& object, const char* name, bool scalar) const {
    const std::string where = "attribute '" + std::string(name) + "' of '" + object + "'";
    const Handle a = open_attribute(object, name, scalar ? "a string" : "an array of strings");
    const Handle type(H5Aget_type(a.id()), H5Tclose, "reading " + where);
    const Handle sp(H5Aget_space(a.id()), H5Sclose, "reading " + where);
    if (H5Tget_class(type.id()) != H5T_STRING || H5Tis_variable_str(type.id()) <= 0 ||
        (scalar && H5Sget_simple_extent_npoints(sp.id()) != 1)) {
      bad(where + " has the wrong type (expected variable-length strings)");
    }
    return read_strings(sp.id(), [&](hid_t mem, void* buf) { return H5Aread(a.id(), mem, buf); }, where);
  }

 private:
  Handle open_dataset(const std::string& path, const std::string& expected) const {
    if (!has(path)) bad("lacks dataset '" + path + "' (expected " + expected + ")");
    return {H5Dopen2(file_->id(), path.c_str(), H5P_DEFAULT), H5Dclose, "opening dataset '" + path + "'"};
  }
  Handle open_attribute(const std::string& object, const char* name, const std::string& expected) const {
    if ((object != "/" && !has(object)) || H5Aexists_by_name(file_->id(), object.c_str(), name, H5P_DEFAULT) <= 0) {
      bad("lacks attribute '" + std::string(name) + "' of '" + object + "' (expected " + expected + ")");
    }
    return {H5Aopen_by_name(file_->id(), object.c_str(), name, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
            "opening attribute '" + std::string(name) + "'"};
  }
  template <class Read>
  std::vector<std::string> read_strings(hid_t sp, Read&& read, const std::string& where) const {
    const hssize_t n = H5Sget_simple_extent_npoints(sp);
    std::vector<std::string> out;
    if (n <= 0) return out;
    const Handle mem = string_type();
    std::vector<char*> buf(static_cast<std::size_t>(n), nullptr);
    check(read(mem.id(), buf.data()), "reading " + where);
    struct Reclaim {  // the library allocated the strings; give them back even if copying throws
      hid_t type, space;
      std::vector<char*>& buf;
      ~Reclaim() { H5Dvlen_reclaim(type, space, H5P_DEFAULT, buf.data()); }
    } reclaim{mem.id(), sp, buf};
    for (const char* s : buf) out.emplace_back(s != nullptr ? s : "");
    return out;
  }

  std::string path_;
  std::optional<Handle> file_;
};

// ---------------------------------------------------------------------------------------------------

/// Refuse to save a state that has blown up: it would replace the last good checkpoint.
void check_finite(const Simulation& sim, const std::string& path) {
  // Bodies (what is integrated) and spheres (a step stopped by the blow-up check leaves its
  // non-finite forces there, the bodies' own still being those of the step before).
  auto refuse = [&](const std::string& what) {
    throw std::runtime_error("not writing checkpoint " + path + ": " + what + " at t = " + std::to_string(sim.time()) +
                             " s (the run has blown up); the previous checkpoint is kept");
  };
  const Bodies& b = sim.bodies();
  for (std::size_t k = 0; k < b.size(); ++k) {
    if (!is_finite(b.x[k]) || !is_finite(b.v[k]) || !is_finite(b.L[k]) || !is_finite(b.force[k]) ||
        !is_finite(b.torque[k])) {
      refuse("body " + std::to_string(b.id[k]) + " has a non-finite position, velocity or force");
    }
  }
  const Particles& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!is_finite(p.x[i]) || !is_finite(p.v[i]) || !is_finite(p.force[i]) || !is_finite(p.torque[i])) {
      refuse("sphere " + std::to_string(p.id[i]) + " has a non-finite position, velocity or force");
    }
  }
}

void write_state(ImageWriter& w, const Simulation& sim) {
  w.attribute("/", "format", std::string(kCheckpointFormat));
  w.attribute<std::int32_t>("/", "format_version", kCheckpointFormatVersion);
  w.attribute("/", "code_version", checkpoint_code_version());
  w.attribute<double>("/", "time", sim.time());
  w.attribute<std::uint64_t>("/", "step", sim.steps());
  w.attribute<double>("/", "dt", sim.dt());
  w.attribute<double>("/", "skin", sim.skin());
  w.attribute<std::uint64_t>("/", "next_sphere_id", sim.next_sphere_id());
  w.attribute<std::uint64_t>("/", "neighbor_builds", sim.neighbors().builds());
  std::vector<std::string> materials, walls;
  for (int m = 0; m < sim.materials().size(); ++m) materials.push_back(sim.materials()[m].name);
  for (const Wall& wall : sim.walls()) walls.push_back(wall.name());
  w.attribute("/", "material_names", materials);
  w.attribute("/", "wall_names", walls);
  w.attribute("/", "shape_names", sim.shape_names());

  // Bodies in id order, as format_version 1 has always had them: the simulation keeps them in its
  // spheres' order (dem/bodies.hpp), which changes no result and is set again on restore, so the
  // file stays readable by every build of this format.
  const Bodies& b = sim.bodies();
  const std::vector<std::size_t> at = b.indices_by_id();
  auto by_id = [&](const auto& field) {
    std::vector<std::decay_t<decltype(field[0])>> out(at.size());
    for (std::size_t k = 0; k < at.size(); ++k) out[k] = field[at[k]];
    return out;
  };
  std::vector<std::uint32_t> sphere_start{0}, sphere_slot;  // the same index, body rows in id order
  sphere_slot.reserve(b.sphere_slot.size());
  for (std::size_t k = 0; k < at.size(); ++k) {
    sphere_slot.insert(sphere_slot.end(), b.sphere_slot.begin() + b.sphere_start[at[k]],
                       b.sphere_slot.begin() + b.sphere_start[at[k] + 1]);
    sphere_start.push_back(static_cast<std::uint32_t>(sphere_slot.size()));
  }
  w.group("/bodies");
  w.dataset("/bodies/id", by_id(b.id));
  w.dataset("/bodies/shape", by_id(b.shape));
  w.dataset("/bodies/mass", by_id(b.mass));
  w.dataset("/bodies/inv_mass", by_id(b.inv_mass));
  w.dataset("/bodies/inertia", by_id(b.inertia));
  w.dataset("/bodies/position", by_id(b.x));
  w.dataset("/bodies/velocity", by_id(b.v));
  w.dataset("/bodies/angular_momentum", by_id(b.L));
  w.dataset("/bodies/angular_velocity", by_id(b.omega));
  w.dataset("/bodies/orientation", by_id(b.q));
  w.dataset("/bodies/force", by_id(b.force));
  w.dataset("/bodies/torque", by_id(b.torque));
  w.dataset("/bodies/sphere_start", sphere_start);
  w.dataset("/bodies/sphere_slot", sphere_slot);

  const Particles& p = sim.particles();
  std::vector<std::uint32_t> body_row(p.size());  // a sphere's body as its row: the body's id
  for (std::size_t s = 0; s < p.size(); ++s) body_row[s] = static_cast<std::uint32_t>(b.id[p.body[s]]);
  w.group("/particles");
  w.dataset("/particles/id", p.id);
  w.dataset("/particles/material", p.material);
  w.dataset("/particles/body", body_row);
  w.dataset("/particles/offset", p.offset);
  w.dataset("/particles/radius", p.radius);
  w.dataset("/particles/body_mass", p.mass);
  w.dataset("/particles/body_inertia", p.inertia);
  w.dataset("/particles/mass_share", p.mass_share);
  w.dataset("/particles/position", p.x);
  w.dataset("/particles/velocity", p.v);
  w.dataset("/particles/angular_velocity", p.omega);
  w.dataset("/particles/force", p.force);
  w.dataset("/particles/torque", p.torque);
  w.dataset("/particles/orientation", p.q);
  w.dataset("/particles/position_at_build", p.x_at_build);

  const NeighborList& nl = sim.neighbors();
  w.group("/neighbors");
  w.dataset("/neighbors/start", nl.starts());
  w.dataset("/neighbors/partner", nl.partners());
  w.dataset("/neighbors/history", nl.histories());
  if (!nl.skins().empty()) w.dataset("/neighbors/skin", nl.skins());
  if (nl.frame().in_wall()) {  // (dem/list_frame.hpp; none: the world's)
    const WallPose& f = nl.frame().at_build;
    w.attribute<std::int32_t>("/neighbors", "frame_wall", nl.frame().wall);
    w.dataset("/neighbors/frame_at_build", std::vector<double>{f.origin.x, f.origin.y, f.origin.z, f.orientation.w,
                                                                f.orientation.x, f.orientation.y, f.orientation.z});
  }

  // Only the wall-contact slots in use (the others are never read).
  const ForceField& ff = sim.force_field();
  // (Particles added since the last step have none yet: the counts may be fewer than the particles.)
  const std::vector<std::uint8_t>& count = ff.wall_counts();
  std::vector<std::int32_t> wall, feature;
  std::vector<ContactHistory> history;
  for (std::size_t i = 0; i < count.size(); ++i) {
    for (int s = 0; s < count[i]; ++s) {
      const WallSlot& ws = ff.wall_slot(i, s);
      wall.push_back(ws.wall);
      feature.push_back(ws.feature);
      history.push_back(ws.history);
    }
  }
  w.group("/wall_contacts");
  w.dataset("/wall_contacts/count", count);
  w.dataset("/wall_contacts/wall", wall);
  w.dataset("/wall_contacts/feature", feature);
  w.dataset("/wall_contacts/history", history);

  w.group("/monitor");
  const ForceDiagnostics& d = sim.diagnostics();
  w.attribute<double>("/monitor", "max_overlap_ratio", d.max_overlap_ratio);
  w.attribute<double>("/monitor", "max_omega_dt", d.max_omega_dt);
  w.attribute<std::uint64_t>("/monitor", "contacts", d.contacts);
  w.attribute<std::uint64_t>("/monitor", "wall_contacts", d.wall_contacts);
  auto stability = [&](const std::string& prefix, const StepStability& s) {
    w.attribute<double>("/monitor", (prefix + "_margin").c_str(), s.margin);
    w.attribute<double>("/monitor", (prefix + "_omega_dt").c_str(), s.omega_dt);
    w.attribute<double>("/monitor", (prefix + "_zeta").c_str(), s.zeta);
    w.attribute<std::int64_t>("/monitor", (prefix + "_body").c_str(), s.body);
    w.attribute<std::int32_t>("/monitor", (prefix + "_contacts").c_str(), s.contacts);
    w.attribute<std::int32_t>("/monitor", (prefix + "_refined").c_str(), s.refined ? 1 : 0);
  };
  stability("stability", sim.stability());
  stability("worst_stability", sim.worst_stability());
  w.attribute<double>("/monitor", "lowest_dt", sim.lowest_dt());
  w.attribute<std::uint64_t>("/monitor", "dt_changes", sim.dt_changes());
}

void write_scenario(ImageWriter& w, const BuiltScenario& run) {
  w.group("/scenario");
  w.attribute("/scenario", "random_state", run.rng.state());
  std::vector<double> next, mass, particle_mass;
  std::vector<std::uint64_t> count, waits;
  std::vector<std::uint8_t> done;
  for (const Pour& pour : run.pours) {
    const Pour::State s = pour.state();
    next.push_back(s.next), mass.push_back(s.mass), particle_mass.push_back(s.particle_mass);
    count.push_back(s.count), waits.push_back(s.waits), done.push_back(s.done ? 1 : 0);
  }
  w.dataset("/scenario/pour_next", next);
  w.dataset("/scenario/pour_mass", mass);
  w.dataset("/scenario/pour_particle_mass", particle_mass);
  w.dataset("/scenario/pour_count", count);
  w.dataset("/scenario/pour_waits", waits);
  w.dataset("/scenario/pour_done", done);
}

void write_run(ImageWriter& w, const RunRecord& r) {
  w.group("/run");
  w.strings("/run/scenario", r.scenario);
  w.attribute<double>("/run", "next_snapshot", r.next_snapshot);
  w.attribute<double>("/run", "wall_seconds", r.wall_seconds);
  w.attribute<std::int32_t>("/run", "settled", r.settled ? 1 : 0);
  w.attribute<std::int32_t>("/run", "warned_stability", r.warned_stability ? 1 : 0);
  w.attribute<std::int32_t>("/run", "complete", r.complete ? 1 : 0);
  w.dataset("/run/snapshot_time", r.snapshot_time);
  w.strings("/run/snapshot_file", r.snapshot_file);
  w.dataset("/run/snapshot_particles", r.snapshot_particles);
}

void write(const std::string& path, const Simulation& sim, const BuiltScenario* run, const RunRecord* record) {
  if (!sim.ready()) throw std::logic_error("write_checkpoint: the simulation has not been set up");
  check_finite(sim, path);
  std::string image;
  {
    const QuietHdf5 quiet;
    try {
      const std::size_t estimate = 65536 + 400 * sim.particles().size() + 56 * sim.neighbors().entries();
      ImageWriter w(estimate);
      write_state(w, sim);
      if (run != nullptr) write_scenario(w, *run);
      if (record != nullptr) write_run(w, *record);
      image = w.finish();
    } catch (const Hdf5Failure& e) {
      throw std::runtime_error("cannot write checkpoint " + path + ": " + e.what());
    }
  }
  write_file_atomically(path, image);  // its errors name the path and the reason
}

/// Identify the file before reading anything else, so that a snapshot or another layout gets a clear
/// answer rather than a missing dataset.
void identify(const Reader& r, int& format_version, std::string& code_version) {
  if (!r.has_attribute("/", "format")) {
    r.bad("is not a grainscale checkpoint (it has no root attribute 'format'; a snapshot, perhaps?)");
  }
  const auto format = r.string_attribute("/", "format", true);
  if (format.empty() || format[0] != kCheckpointFormat) {
    r.bad("is not a grainscale checkpoint (root attribute 'format' is not '" + std::string(kCheckpointFormat) + "')");
  }
  format_version = r.attribute<std::int32_t>("/", "format_version");
  code_version = r.string_attribute("/", "code_version", true)[0];
  if (format_version != kCheckpointFormatVersion) {
    r.bad("has format_version " + std::to_string(format_version) + " (written by grainscale " + code_version +
          "); this build reads only format_version " + std::to_string(kCheckpointFormatVersion));
  }
}

}  // namespace

CheckpointInfo read_checkpoint_info(const std::string& path) {
  const QuietHdf5 quiet;
  CheckpointInfo info;
  try {
    const Reader r(path);
    int format_version = 0;
    identify(r, format_version, info.code_version);
    info.time = r.attribute<double>("/", "time");
    info.step = r.attribute<std::uint64_t>("/", "step");
    info.has_run = r.has("/run");
    if (info.has_run) info.complete = r.attribute<std::int32_t>("/run", "complete") != 0;
  } catch (const Hdf5Failure& e) {
    throw InputError("checkpoint '" + path + "': " + e.what());
  }
  return info;
}

std::string checkpoint_code_version() { return std::string(grainscale::version) + " " + grainscale::git_revision; }

void write_checkpoint(const std::string& path, const Simulation& sim) { write(path, sim, nullptr, nullptr); }

void write_checkpoint(const std::string& path, const BuiltScenario& run, const RunRecord* record) {
  write(path, *run.sim, &run, record);
}

Checkpoint read_checkpoint(const std::string& path) {
  const QuietHdf5 quiet;
  Checkpoint c;
  c.path = path;
  try {
    const Reader r(path);
    identify(r, c.format_version, c.code_version);
    SimulationState& s = c.simulation;
    s.time = r.attribute<double>("/", "time");
    s.steps = r.attribute<std::uint64_t>("/", "step");
    s.dt = r.attribute<double>("/", "dt");
    s.skin = r.attribute<double>("/", "skin");
    s.next_sphere_id = r.attribute<std::uint64_t>("/", "next_sphere_id");
    s.neighbor_builds = r.attribute<std::uint64_t>("/", "neighbor_builds");
    c.material_names = r.string_attribute("/", "material_names", false);
    c.wall_names = r.string_attribute("/", "wall_names", false);
    s.shape_names = r.string_attribute("/", "shape_names", false);

    Bodies& b = s.bodies;
    b.id = r.dataset<std::uint64_t>("/bodies/id");
    const hsize_t nb = b.id.size();
    b.shape = r.dataset<std::int32_t>("/bodies/shape", nb);
    b.mass = r.dataset<double>("/bodies/mass", nb);
    b.inv_mass = r.dataset<double>("/bodies/inv_mass", nb);
    b.inertia = r.dataset<Vec3>("/bodies/inertia", nb);
    b.x = r.dataset<Vec3>("/bodies/position", nb);
    b.v = r.dataset<Vec3>("/bodies/velocity", nb);
    b.L = r.dataset<Vec3>("/bodies/angular_momentum", nb);
    b.omega = r.dataset<Vec3>("/bodies/angular_velocity", nb);
    b.q = r.dataset<Quat>("/bodies/orientation", nb);
    b.force = r.dataset<Vec3>("/bodies/force", nb);
    b.torque = r.dataset<Vec3>("/bodies/torque", nb);
    b.sphere_start = r.dataset<std::uint32_t>("/bodies/sphere_start", nb + 1);

    Particles& p = s.particles;
    p.id = r.dataset<std::uint64_t>("/particles/id");
    const hsize_t n = p.id.size();
    b.sphere_slot = r.dataset<std::uint32_t>("/bodies/sphere_slot", n);
    p.material = r.dataset<std::int32_t>("/particles/material", n);
    p.body = r.dataset<std::uint32_t>("/particles/body", n);
    p.offset = r.dataset<Vec3>("/particles/offset", n);
    p.radius = r.dataset<double>("/particles/radius", n);
    p.mass = r.dataset<double>("/particles/body_mass", n);
    p.inertia = r.dataset<double>("/particles/body_inertia", n);
    p.mass_share = r.dataset<double>("/particles/mass_share", n);
    p.x = r.dataset<Vec3>("/particles/position", n);
    p.v = r.dataset<Vec3>("/particles/velocity", n);
    p.omega = r.dataset<Vec3>("/particles/angular_velocity", n);
    p.force = r.dataset<Vec3>("/particles/force", n);
    p.torque = r.dataset<Vec3>("/particles/torque", n);
    p.q = r.dataset<Quat>("/particles/orientation", n);
    p.x_at_build = r.dataset<Vec3>("/particles/position_at_build", n);

    s.neighbor_start = r.dataset<std::uint32_t>("/neighbors/start");
    s.neighbor_partner = r.dataset<std::uint32_t>("/neighbors/partner");
    s.neighbor_history = r.dataset<ContactHistory>("/neighbors/history", s.neighbor_partner.size());
    // (Files written before 2026-12-06 have none: one skin for all, the attribute's.)
    if (r.has("/neighbors/skin") && !s.neighbor_start.empty()) {
      s.neighbor_skin = r.dataset<double>("/neighbors/skin", s.neighbor_start.size() - 1);
    }
    // (Files written before 2026-12-06's afternoon, and lists measured in the world, have none.)
    if (r.has_attribute("/neighbors", "frame_wall")) {
      s.neighbor_frame_wall = r.attribute<std::int32_t>("/neighbors", "frame_wall");
      const std::vector<double> f = r.dataset<double>("/neighbors/frame_at_build", 7);
      s.neighbor_frame_at_build.origin = {f[0], f[1], f[2]};
      s.neighbor_frame_at_build.orientation = {f[3], f[4], f[5], f[6]};
    }

    s.wall_count = r.dataset<std::uint8_t>("/wall_contacts/count");
    const std::vector<std::int32_t> wall = r.dataset<std::int32_t>("/wall_contacts/wall");
    const std::vector<std::int32_t> feature = r.dataset<std::int32_t>("/wall_contacts/feature", wall.size());
    const std::vector<ContactHistory> history = r.dataset<ContactHistory>("/wall_contacts/history", wall.size());
    s.wall_slots.resize(wall.size());
    for (std::size_t k = 0; k < wall.size(); ++k) s.wall_slots[k] = {wall[k], feature[k], history[k]};

    ForceDiagnostics& d = s.diagnostics;
    d.max_overlap_ratio = r.attribute<double>("/monitor", "max_overlap_ratio");
    d.max_omega_dt = r.attribute<double>("/monitor", "max_omega_dt");
    d.contacts = r.attribute<std::uint64_t>("/monitor", "contacts");
    d.wall_contacts = r.attribute<std::uint64_t>("/monitor", "wall_contacts");
    auto stability = [&](const std::string& prefix) {
      StepStability st;
      st.margin = r.attribute<double>("/monitor", (prefix + "_margin").c_str());
      st.omega_dt = r.attribute<double>("/monitor", (prefix + "_omega_dt").c_str());
      st.zeta = r.attribute<double>("/monitor", (prefix + "_zeta").c_str());
      st.body = r.attribute<std::int64_t>("/monitor", (prefix + "_body").c_str());
      st.contacts = r.attribute<std::int32_t>("/monitor", (prefix + "_contacts").c_str());
      st.refined = r.attribute<std::int32_t>("/monitor", (prefix + "_refined").c_str()) != 0;
      return st;
    };
    s.stability = stability("stability");
    s.worst_stability = stability("worst_stability");
    if (r.has_attribute("/monitor", "lowest_dt")) {  // (since 2026-12-07: the step control's record)
      s.lowest_dt = r.attribute<double>("/monitor", "lowest_dt");
      s.dt_changes = r.attribute<std::uint64_t>("/monitor", "dt_changes");
    }

    if (r.has("/scenario")) {
      c.has_scenario = true;
      c.random = r.string_attribute("/scenario", "random_state", true)[0];
      const auto next = r.dataset<double>("/scenario/pour_next");
      const hsize_t np = next.size();
      const auto mass = r.dataset<double>("/scenario/pour_mass", np);
      const auto particle_mass = r.dataset<double>("/scenario/pour_particle_mass", np);
      const auto count = r.dataset<std::uint64_t>("/scenario/pour_count", np);
      const auto waits = r.dataset<std::uint64_t>("/scenario/pour_waits", np);
      const auto done = r.dataset<std::uint8_t>("/scenario/pour_done", np);
      for (std::size_t k = 0; k < np; ++k) {
        c.pours.push_back({next[k], mass[k], particle_mass[k], count[k], waits[k], done[k] != 0});
      }
    }
    if (r.has("/run")) {
      c.has_run = true;
      RunRecord& run = c.run;
      run.scenario = r.strings("/run/scenario");
      run.next_snapshot = r.attribute<double>("/run", "next_snapshot");
      run.wall_seconds = r.attribute<double>("/run", "wall_seconds");
      run.settled = r.attribute<std::int32_t>("/run", "settled") != 0;
      run.warned_stability = r.attribute<std::int32_t>("/run", "warned_stability") != 0;
      run.complete = r.attribute<std::int32_t>("/run", "complete") != 0;
      run.snapshot_time = r.dataset<double>("/run/snapshot_time");
      run.snapshot_file = r.strings("/run/snapshot_file");
      run.snapshot_particles = r.dataset<std::uint64_t>("/run/snapshot_particles", run.snapshot_time.size());
      if (run.snapshot_file.size() != run.snapshot_time.size()) {
        r.bad("dataset '/run/snapshot_file' and '/run/snapshot_time' differ in length");
      }
    }
  } catch (const Hdf5Failure& e) {
    throw InputError("checkpoint '" + path + "': " + e.what());
  }
  return c;
}

void restore_checkpoint(Checkpoint&& c, Simulation& sim) {
  auto bad = [&](const std::string& why) { throw InputError("checkpoint '" + c.path + "': " + why); };
  std::vector<std::string> materials, walls;
  for (int m = 0; m < sim.materials().size(); ++m) materials.push_back(sim.materials()[m].name);
  for (const Wall& w : sim.walls()) walls.push_back(w.name());
  auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
    return "[" + s + "]";
  };
  if (materials != c.material_names) {
    bad("was written with materials " + list(c.material_names) + ", this simulation has " + list(materials));
  }
  if (walls != c.wall_names) bad("was written with walls " + list(c.wall_names) + ", this simulation has " + list(walls));
  try {
    sim.restore(std::move(c.simulation));
  } catch (const std::invalid_argument& e) {
    bad(std::string("inconsistent state: ") + e.what());
  }
}

void restore_checkpoint(Checkpoint&& c, BuiltScenario& run) {
  auto bad = [&](const std::string& why) { throw InputError("checkpoint '" + c.path + "': " + why); };
  if (!c.has_scenario) bad("holds a bare simulation, not a scenario run (no '/scenario' group)");
  if (c.pours.size() != run.pours.size()) {
    bad("has " + std::to_string(c.pours.size()) + " pours, the scenario " + std::to_string(run.pours.size()));
  }
  Random rng = run.rng;
  try {
    rng.set_state(c.random);
  } catch (const std::invalid_argument&) {
    bad("attribute 'random_state' of '/scenario' is not a random generator state");
  }
  const std::vector<Pour::State> pours = std::move(c.pours);
  restore_checkpoint(std::move(c), *run.sim);  // checks everything else; throws before any change
  run.rng = rng;
  for (std::size_t k = 0; k < pours.size(); ++k) run.pours[k].restore(pours[k]);
}

}  // namespace grainscale::dem
