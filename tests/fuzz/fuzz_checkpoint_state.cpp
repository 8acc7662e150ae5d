// Structure-aware: a valid checkpoint (corpus/checkpoint/small.h5) whose state the fuzz input edits -
// numbers overwritten, arrays cut short or lengthened - and which is then restored and stepped. This
// reaches Simulation::restore's consistency checks and the first steps after them, which a fuzzed HDF5
// file mostly cannot (libhdf5 rejects, or in 1.10 sometimes hangs on, the corrupt file first).
// Input: a sequence of 12-byte edits {array (1 byte), operation (1), index (2), value (8)}.
#include <cstring>
#include <memory>

#include "dem/checkpoint.hpp"
#include "dem/input_error.hpp"
#include "dem/walls/plane.hpp"
#include "fuzz_input_file.hpp"

namespace {

using namespace grainscale::dem;

const Checkpoint& base() {
  static const Checkpoint c = read_checkpoint(GRAINSCALE_FUZZ_CORPUS "/checkpoint/small.h5");
  return c;
}

template <class T>
void edit(std::vector<T>& v, int op, std::uint16_t index, const unsigned char* value) {
  if (op == 1) {
    v.resize(std::min<std::size_t>(v.size(), index));  // cut short
  } else if (op == 2) {
    v.resize(v.size() + 1 + index % 4);  // lengthen with zeros
  } else if (!v.empty()) {
    // Overwrite some bytes of one element with the value.
    T& e = v[index % v.size()];
    std::memcpy(reinterpret_cast<unsigned char*>(&e) + (op % 4) * sizeof(double) % sizeof(T), value,
                std::min<std::size_t>(8, sizeof(T) - (op % 4) * sizeof(double) % sizeof(T)));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Checkpoint c = base();
  SimulationState& s = c.simulation;
  for (std::size_t k = 0; k + 12 <= size; k += 12) {
    const int array = data[k] % 24, op = data[k + 1] % 8;
    std::uint16_t index;
    std::memcpy(&index, data + k + 2, 2);
    const unsigned char* value = data + k + 4;
    Particles& p = s.particles;
    Bodies& b = s.bodies;
    switch (array) {
      case 0: edit(p.id, op, index, value); break;
      case 1: edit(p.material, op, index, value); break;
      case 2: edit(p.body, op, index, value); break;
      case 3: edit(p.radius, op, index, value); break;
      case 4: edit(p.x, op, index, value); break;
      case 5: edit(p.x_at_build, op, index, value); break;
      case 6: edit(p.v, op, index, value); break;
      case 7: edit(p.offset, op, index, value); break;
      case 8: edit(p.mass, op, index, value); break;
      case 9: edit(b.id, op, index, value); break;
      case 10: edit(b.shape, op, index, value); break;
      case 11: edit(b.mass, op, index, value); break;
      case 12: edit(b.x, op, index, value); break;
      case 13: edit(b.q, op, index, value); break;
      case 14: edit(b.inertia, op, index, value); break;
      case 15: edit(b.sphere_start, op, index, value); break;
      case 16: edit(s.neighbor_start, op, index, value); break;
      case 17: edit(s.neighbor_partner, op, index, value); break;
      case 18: edit(s.neighbor_history, op, index, value); break;
      case 19: edit(s.wall_count, op, index, value); break;
      case 20: edit(s.wall_slots, op, index, value); break;
      case 21: std::memcpy(&s.dt, value, 8); break;
      case 22: std::memcpy(&s.skin, value, 8); break;
      default: std::memcpy(&s.next_sphere_id, value, 8); break;
    }
  }
  MaterialTable mt;
  mt.add({"grain", 1000, 1e6, 0.3});
  mt.add({"wall", 1000, 1e8, 0.3});
  mt.set_pair(0, 0, {0.5, 0.5, 0.1, true});
  mt.set_pair(0, 1, {0.5, 0.5, 0.1, true});
  Simulation sim(mt, SimulationSettings{});
  sim.add_wall("floor", std::make_shared<PlaneGeometry>(Vec3{0, 0, 0}, Vec3{0, 0, 1}), 1);
  try {
    restore_checkpoint(std::move(c), sim);
  } catch (const grainscale::InputError&) {
    return 0;
  }
  try {
    sim.run_steps(3);
  } catch (const BlowUp&) {  // a restored state may be physically absurd; stopping it is the right answer
  } catch (const grainscale::InputError&) {
  }
  return 0;
}
