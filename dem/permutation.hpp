#pragma once
// Renumbering a structure of arrays: new slot i takes what old slot new_to_old[i] held. Spheres and
// bodies are renumbered this way at every neighbour-list build (dem/particles.hpp, dem/bodies.hpp).
#include <cstdint>
#include <tuple>
#include <vector>

#include "dem/parallel.hpp"
#include "dem/quaternion.hpp"
#include "dem/vec3.hpp"

namespace grainscale::dem {

/// Apply `new_to_old` to one array through a scratch buffer (swap keeps both capacities).
template <class T>
void permute_array(std::vector<T>& a, std::vector<T>& scratch, const std::vector<std::uint32_t>& new_to_old) {
  scratch.resize(a.size());
  const std::size_t n = a.size();
#pragma omp parallel for if(n >= parallel_min_items()) schedule(static)
  for (std::size_t i = 0; i < n; ++i) scratch[i] = a[new_to_old[i]];
  a.swap(scratch);
}

/// One scratch buffer per element type, so that a struct of arrays is permuted field by field
/// without allocating once the buffers have reached its size.
class PermuteScratch {
 public:
  template <class T>
  void apply(std::vector<T>& a, const std::vector<std::uint32_t>& new_to_old) {
    permute_array(a, std::get<std::vector<T>>(buffers_), new_to_old);
  }

 private:
  std::tuple<std::vector<double>, std::vector<Vec3>, std::vector<Quat>, std::vector<std::uint64_t>,
             std::vector<std::int32_t>, std::vector<std::uint32_t>>
      buffers_;
};

}  // namespace grainscale::dem
