#pragma once
// The wall-contact histories of every sphere, double-buffered (this step's and last step's): up to
// kSlots per sphere, slot-major (sphere i's slot s at [s * stride + i]: the first slots of
// neighbouring spheres share cache lines and a bed's floor contacts are read as one stream), of which
// the first count(i) are in use. Only slots in use are ever written or read.
//
// Why a class and not two std::vectors: a vector writes every element when it grows or is copied,
// so all 2 x 8 slots of every sphere became resident memory (896 bytes per sphere, more than half
// of a settled bed's), although a bed on a floor uses slot 0 of a sphere on the floor and the other
// slots of a few spheres at the side walls. Here the buffers are allocated without being written
// and resized, permuted and copied slot by slot in use, so the pages of slots no sphere uses are never
// touched and the operating system never maps them (docs/performance.md, memory per sphere).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include "dem/contact/contact_kinematics.hpp"
#include "dem/parallel.hpp"
#include "dem/permutation.hpp"

namespace grainscale::dem {

/// Tangential history of one particle-wall contact, keyed by (wall, feature).
struct WallSlot {
  std::int32_t wall = -1;
  std::int32_t feature = 0;
  ContactHistory history;
};

class WallSlots {
 public:
  static constexpr int kSlots = 8;

  WallSlots() = default;
  WallSlots(const WallSlots& other) { *this = other; }
  WallSlots& operator=(const WallSlots& other) {
    if (this == &other) return *this;
    stride_ = other.stride_;
    now_ = allocate(stride_), before_ = allocate(stride_);
    count_ = other.count_, before_count_ = other.before_count_;
    copy_in_use(other.now_.get(), stride_, count_.data(), stride_, now_.get(), stride_);
    copy_in_use(other.before_.get(), stride_, before_count_.data(), stride_, before_.get(), stride_);
    return *this;
  }
  // (A moved-from WallSlots is empty, room for no sphere, and usable.)
  WallSlots(WallSlots&& other) noexcept { *this = std::move(other); }
  WallSlots& operator=(WallSlots&& other) noexcept {
    now_ = std::move(other.now_), before_ = std::move(other.before_);
    count_ = std::move(other.count_), before_count_ = std::move(other.before_count_);
    stride_ = std::exchange(other.stride_, 0);
    other.count_.clear(), other.before_count_.clear();
    return *this;
  }

  /// Spheres there is room for (the distance between one slot of a sphere and the next).
  std::size_t stride() const { return stride_; }
  /// This step's slots of sphere i (slot s at [s * stride()]) and how many are in use.
  WallSlot* now(std::size_t i) { return now_.get() + i; }
  const WallSlot* now(std::size_t i) const { return now_.get() + i; }
  const WallSlot& now(std::size_t i, int s) const { return now_[s * stride_ + i]; }
  std::uint8_t* counts() { return count_.data(); }
  const std::vector<std::uint8_t>& counts_vector() const { return count_; }
  /// Last step's, while a step computes this step's.
  const WallSlot* before(std::size_t i) const { return before_.get() + i; }
  const std::uint8_t* before_counts() const { return before_count_.data(); }

  /// At the start of a step: this step's become last step's, and this step's are written afresh.
  void flip() {
    now_.swap(before_);
    count_.swap(before_count_);
  }

  /// Room for n spheres: the slots in use of the first min(n, stride()) kept, the rest none.
  void resize(std::size_t n) {
    if (n == stride_) return;
    auto relayout = [&](Buffer& slots, std::vector<std::uint8_t>& count) {
      Buffer moved = allocate(n);
      count.resize(n, 0);
      copy_in_use(slots.get(), stride_, count.data(), std::min(n, stride_), moved.get(), n);
      slots.swap(moved);
    };
    relayout(now_, count_);
    relayout(before_, before_count_);
    stride_ = n;
  }

  /// This step's slots renumbered with the spheres: new sphere i holds what new_to_old[i] held
  /// (last step's are scratch here and hold nothing after it).
  void permute(const std::vector<std::uint32_t>& new_to_old) { permute(Renumbering(new_to_old)); }
  /// The same; when the renumbering lists the slots it moves, only theirs are copied, through last
  /// step's slots (scratch here) and back (dem/permutation.hpp: a bed at rest moves ~1 % of them).
  void permute(const Renumbering& r) {
    const std::vector<std::uint32_t>& new_to_old = r.new_to_old();
    const std::size_t n = new_to_old.size();
    resize(n);
    if (r.sparse()) {
      const std::vector<std::uint32_t>& moved = r.moved();
      for (const std::uint32_t i : moved) {  // the moved slots' new contents, in last step's buffer
        const std::size_t from = new_to_old[i];
        for (int s = 0; s < count_[from]; ++s) before_[s * n + i] = now_[s * n + from];
        before_count_[i] = count_[from];
      }
      for (const std::uint32_t i : moved) {
        for (int s = 0; s < before_count_[i]; ++s) now_[s * n + i] = before_[s * n + i];
        count_[i] = before_count_[i];
      }
      std::fill(before_count_.begin(), before_count_.end(), 0);  // (as below)
      return;
    }
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t from = new_to_old[i];
      for (int s = 0; s < count_[from]; ++s) before_[s * n + i] = now_[s * n + from];
      before_count_[i] = count_[from];
    }
    now_.swap(before_);
    count_.swap(before_count_);
    std::fill(before_count_.begin(), before_count_.end(), 0);  // (a copy reads the slots counts name)
  }

  /// These slots for `counts.size()` spheres from the slots in use, sphere by sphere (the caller
  /// has checked that `used` holds sum(counts) slots and every count is at most kSlots).
  void assign(const std::vector<std::uint8_t>& counts, const std::vector<WallSlot>& used) {
    const std::size_t n = counts.size();
    stride_ = n;
    now_ = allocate(n), before_ = allocate(n);
    count_ = counts;
    before_count_.assign(n, 0);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (int s = 0; s < counts[i]; ++s) now_[s * n + i] = used[k++];
  }

  /// Bytes allocated (not all resident: see above).
  std::size_t bytes() const { return 2 * stride_ * (kSlots * sizeof(WallSlot) + 1); }

 private:
  struct Free {
    void operator()(WallSlot* p) const { std::free(p); }
  };
  using Buffer = std::unique_ptr<WallSlot[], Free>;

  /// kSlots x n slots, not initialised: WallSlot is an aggregate, so writing one creates it (C++20
  /// [intro.object]/10, as dem/uninitialized_array.hpp).
  static Buffer allocate(std::size_t n) {
    if (n == 0) return Buffer();
    void* p = std::malloc(n * kSlots * sizeof(WallSlot));
    if (p == nullptr) throw std::bad_alloc();
    return Buffer(static_cast<WallSlot*>(p));
  }

  /// The slots in use of the first `spheres` spheres, from one slot-major layout to another.
  static void copy_in_use(const WallSlot* from, std::size_t from_stride, const std::uint8_t* count,
                          std::size_t spheres, WallSlot* to, std::size_t to_stride) {
    for (std::size_t i = 0; i < spheres; ++i)
      for (int s = 0; s < count[i]; ++s) to[s * to_stride + i] = from[s * from_stride + i];
  }

  Buffer now_, before_;
  std::vector<std::uint8_t> count_, before_count_;
  std::size_t stride_ = 0;
};

}  // namespace grainscale::dem
