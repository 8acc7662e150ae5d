// Gridded flow input (continuum/gridded_flow.hpp), structure-aware: the fuzz input describes a flow
// file - layout (plain or coarse-grained field file), grid size, every value, shape mismatches, the
// frame count and the frame asked for - which is written as a valid HDF5 file, loaded with
// GriddedFlow::load and evaluated (stream function, shear rate, surface) inside and outside the bed.
// Bad input must end in InputError.
//
// Input: 6 header bytes {flags, nx, nz, frame count, frame, length}, then one selector byte per value
// (x, z, u or velocity, shear rate, surface height in file order): 0 the regular default, 1 the next
// 8 bytes as a double, 2 the default scaled by (1 + int8 / 64), 3 a special value (NaN, inf, 0, ...).
#include <cmath>
#include <cstring>
#include <limits>

#include "continuum/gridded_flow.hpp"
#include "dem/input_error.hpp"
#include "fuzz_flow_file.hpp"
#include "fuzz_input_file.hpp"

namespace {

class Bytes {
 public:
  Bytes(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  std::uint8_t byte() { return k_ < n_ ? d_[k_++] : 0; }
  double value(double fallback) {
    static const double special[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                                     -std::numeric_limits<double>::infinity(), 0.0, -1.0, 1e308, 1e-308, -0.0};
    switch (byte() % 4) {
      case 1: {
        double v = fallback;
        if (k_ + 8 <= n_) std::memcpy(&v, d_ + k_, 8), k_ += 8;
        return v;
      }
      case 2: return fallback * (1 + static_cast<std::int8_t>(byte()) / 64.0);
      case 3: return special[byte() % 8];
      default: return fallback;
    }
  }

 private:
  const std::uint8_t* d_;
  std::size_t n_, k_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using grainscale::fuzz::write_h5_dataset;
  using grainscale::fuzz::write_h5_int_attribute;
  Bytes in(data, size);
  const std::uint8_t flags = in.byte();
  const bool cg = flags & 1;
  const int mismatch = (flags >> 1) & 3;  // 1: u one column wider, 2: h one short, 3: u flattened
  const std::size_t nx = in.byte() % 9, nz = in.byte() % 9;
  const int count = static_cast<std::int8_t>(in.byte());
  const int frame = static_cast<std::int8_t>(in.byte());
  const double length = 1.0 + static_cast<std::int8_t>(in.byte()) / 64.0;

  std::vector<double> x(nx), z(nz), h(nx), rate(nz * nx), u(nz * (nx + (mismatch == 1)) * (cg ? 3 : 1));
  for (std::size_t j = 0; j < nx; ++j) x[j] = in.value(length * (j + 1.0) / (nx + 1.0));
  for (std::size_t k = 0; k < nz; ++k) z[k] = in.value(0.1 * k / std::max<std::size_t>(nz - 1, 1));
  for (std::size_t m = 0; m < u.size(); ++m) u[m] = in.value(0.01 * (m % 7 == 0 ? -1.0 : 0.5));
  for (double& v : rate) v = in.value(0.1);
  for (double& v : h) v = in.value(0.1);
  if (mismatch == 2 && !h.empty()) h.pop_back();

  const std::string path = (grainscale::fuzz::work_dir() / "fuzzed_flow.h5").string();
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f < 0) return 0;
  bool ok = true;
  const hsize_t unx = nx + (mismatch == 1);
  if (cg) {
    ok = ok && write_h5_int_attribute(f, "/", "cg_layout_version", 1);
    ok = ok && write_h5_int_attribute(f, "/grid", "dimension", flags & 8 ? 3 : 2);
    ok = ok && write_h5_int_attribute(f, "/frames", "count", count);
    ok = ok && write_h5_dataset(f, "/grid/x", {nx}, x) && write_h5_dataset(f, "/grid/z", {nz}, z);
    const std::string fr = "/frames/000000/";
    if (mismatch == 3) ok = ok && write_h5_dataset(f, fr + "mixture/velocity", {u.size()}, u);
    else ok = ok && write_h5_dataset(f, fr + "mixture/velocity", {nz, 1, unx, 3}, u);
    ok = ok && write_h5_dataset(f, fr + "shear_rate", {nz, 1, nx}, rate);
    ok = ok && write_h5_dataset(f, fr + "surface_height", {1, h.size()}, h);
  } else {
    ok = ok && write_h5_dataset(f, "/x", {nx}, x) && write_h5_dataset(f, "/z", {nz}, z);
    if (mismatch == 3) ok = ok && write_h5_dataset(f, "/u", {u.size()}, u);
    else ok = ok && write_h5_dataset(f, "/u", {nz, unx}, u);
    ok = ok && write_h5_dataset(f, "/shear_rate", {nz, nx}, rate);
    ok = ok && write_h5_dataset(f, "/surface_height", {h.size()}, h);
  }
  H5Fclose(f);
  if (!ok) return 0;
  try {
    const auto flow = grainscale::continuum::GriddedFlow::load(path, length, frame);
    for (double xs : {-0.1, 0.0, 0.3, 0.5 * length, length, length + 0.1}) {
      (void)flow.surface_height(xs);
      for (double zs : {-0.01, 0.0, 0.05, 0.2}) {
        (void)flow.stream_function(xs, zs, 0.0);
        (void)flow.shear_rate(xs, zs, 0.0);
      }
    }
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
