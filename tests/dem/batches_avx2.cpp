// The batched contact models compiled for AVX2 without AVX-512 (-march=x86-64-v3, tests/CMakeLists.txt),
// whatever this machine has, so that tests/dem/batches_vectorised.sh can check that they vectorise on
// such CPUs too: with AVX-512, GCC masks what it cannot if-convert, and the check would pass on this
// machine while the portable build ran them one contact at a time (CMakeLists.txt, -fno-trapping-math).
#include "dem/contact/rolling_constant_torque.hpp"
#include "dem/contact/rolling_epsd.hpp"
#include "dem/contact/rolling_none.hpp"
#include "dem/pair_batch.hpp"
#include "dem/wall_batch.hpp"

namespace grainscale::dem {
template struct PairBatch<ConstantTorqueRolling>;
template struct PairBatch<EpsdRolling>;
template struct WallBatch<ConstantTorqueRolling>;
template struct WallBatch<EpsdRolling>;
}  // namespace grainscale::dem
