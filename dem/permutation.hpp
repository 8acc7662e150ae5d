#pragma once
// Renumbering a structure of arrays: new slot i takes what old slot new_to_old[i] held. Spheres and
// bodies are renumbered this way at every neighbour-list build (dem/particles.hpp, dem/bodies.hpp).
//
// A build sorts the spheres by cell, and in a bed at rest few change cell from one build to the
// next: in the 10^5-sphere bed of bench/run_scaling.sh, 5 to 3,900 slots of 100,000 (~1 %), in
// runs as long as a row of cells, since a sphere that changes cell shifts the slots between its old
// place and its new one by one. So a Renumbering lists the slots it moves, and when they are few
// every array is renumbered through those alone: O(moved) loads and stores instead of reading and
// writing the whole array (and its scratch copy) once per array, some 25 arrays a build, in beds far
// beyond the caches. The arrays end up the same, element for element.
#include <cstdint>
#include <tuple>
#include <vector>

#include "dem/parallel.hpp"
#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

/// new_to_old, and the slots it moves (new_to_old[i] != i, ascending) when they are few enough.
class Renumbering {
 public:
  /// Moving more than this share of the slots, the arrays are renumbered whole (a listed slot costs
  /// a scattered load and store; a whole array, in order, one of each per slot).
  static constexpr std::size_t kSparseShare = 8;  // 1/8

  Renumbering() = default;
  // A copy is empty, as a new one: it would refer to the original's new_to_old (a Simulation's
  // copy holds its own, which its next build assigns).
  Renumbering(const Renumbering&) {}
  Renumbering& operator=(const Renumbering&) {
    new_to_old_ = nullptr, moved_.clear(), sparse_ = false;
    return *this;
  }
  /// (For tests and code outside the step loop: lists the moved slots at once.)
  explicit Renumbering(const std::vector<std::uint32_t>& new_to_old) { assign(new_to_old); }

  /// Takes `new_to_old` (held by reference: it must outlive this) and lists the slots it moves.
  /// Allocation-free once the list has reached its largest size.
  void assign(const std::vector<std::uint32_t>& new_to_old) {
    new_to_old_ = &new_to_old;
    const std::size_t n = new_to_old.size(), most = n / kSparseShare;
    moved_.clear();
    sparse_ = true;
    for (std::size_t i = 0; i < n; ++i) {
      if (new_to_old[i] == i) continue;
      if (moved_.size() == most) {  // too many: renumber whole
        sparse_ = false;
        moved_.clear();
        return;
      }
      moved_.push_back(static_cast<std::uint32_t>(i));
    }
  }

  const std::vector<std::uint32_t>& new_to_old() const { return *new_to_old_; }
  /// Whether moved() lists every slot that changes (else every slot is renumbered).
  bool sparse() const { return sparse_; }
  const std::vector<std::uint32_t>& moved() const { return moved_; }

 private:
  const std::vector<std::uint32_t>* new_to_old_ = nullptr;
  std::vector<std::uint32_t> moved_;
  bool sparse_ = false;
};

/// Apply a renumbering to one array through a scratch buffer. Whole: every element copied into the
/// scratch in the new order, then the two swapped (both capacities kept). Sparse: the moved slots'
/// new contents gathered into the scratch, then stored in place; new_to_old maps the moved slots
/// onto themselves (the others are its fixed points), so no element is overwritten before it is read.
template <class T>
void permute_array(std::vector<T>& a, std::vector<T>& scratch, const Renumbering& r) {
  const std::vector<std::uint32_t>& new_to_old = r.new_to_old();
  const std::size_t n = a.size();
  if (r.sparse()) {
    const std::vector<std::uint32_t>& moved = r.moved();
    const std::size_t m = moved.size();
    if (scratch.size() < m) scratch.resize(m);  // (never shrunk: a whole renumbering would refill it)
    for (std::size_t k = 0; k < m; ++k) scratch[k] = a[new_to_old[moved[k]]];
    for (std::size_t k = 0; k < m; ++k) a[moved[k]] = scratch[k];
    return;
  }
  scratch.resize(n);
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static)
  for (std::size_t i = 0; i < n; ++i) scratch[i] = a[new_to_old[i]];
  a.swap(scratch);
}

/// One scratch buffer per element type, so that a struct of arrays is permuted field by field
/// without allocating once the buffers have reached its size.
class PermuteScratch {
 public:
  template <class T>
  void apply(std::vector<T>& a, const Renumbering& r) {
    permute_array(a, std::get<std::vector<T>>(buffers_), r);
  }

 private:
  std::tuple<std::vector<double>, std::vector<Vec3>, std::vector<Quat>, std::vector<std::uint64_t>,
             std::vector<std::int32_t>, std::vector<std::uint32_t>>
      buffers_;
};

}  // namespace grainscale::dem
