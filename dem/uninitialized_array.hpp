#pragma once
// Fixed-capacity scratch storage that is NOT zeroed. Vec3 and the contact structs have default member
// initialisers, so a plain `WallHit hits[16]` zeroes ~1.6 kB per particle per step, which profiling
// showed costing as much as the pair forces. The element types are aggregates, i.e. implicit-lifetime
// types, so writing into this storage creates the objects (C++20 [intro.object]/10).
#include <cstddef>
#include <type_traits>

namespace grainscale::dem {

template <class T, std::size_t N>
class UninitializedArray {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

 public:
  T* data() { return reinterpret_cast<T*>(storage_); }
  T& operator[](std::size_t i) { return data()[i]; }
  static constexpr std::size_t capacity() { return N; }

 private:
  alignas(T) unsigned char storage_[N * sizeof(T)];
};

}  // namespace grainscale::dem
