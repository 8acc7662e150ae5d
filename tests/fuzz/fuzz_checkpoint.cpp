// HDF5 checkpoints (dem/checkpoint.hpp): read, then restored into a simulation with the materials and
// walls the corpus's checkpoints name, which runs every consistency check of Simulation::restore.
#include <memory>

#include "dem/checkpoint.hpp"
#include "dem/input_error.hpp"
#include "dem/walls/plane.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace grainscale::dem;
  const std::string path = grainscale::fuzz::input_file(data, size, "fuzzed_checkpoint.h5");
  try {
    Checkpoint c = read_checkpoint(path);
    MaterialTable mt;
    mt.add({"grain", 1000, 1e6, 0.3});
    mt.add({"wall", 1000, 1e8, 0.3});
    mt.set_pair(0, 0, {0.5, 0.5, 0.1, true});
    mt.set_pair(0, 1, {0.5, 0.5, 0.1, true});
    Simulation sim(mt, SimulationSettings{});
    sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
    restore_checkpoint(std::move(c), sim);
    sim.run_steps(2);
  } catch (const grainscale::InputError&) {
  } catch (const BlowUp&) {  // a restored state may be physically absurd; stopping it is the right answer
  }
  return 0;
}
