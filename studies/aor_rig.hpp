#pragma once
// The source report's angle-of-repose rig as a DEM scenario (docs/aor_calibration.md):
//
//   "a sample was placed in a pipe (100mm diameter and 300mm long). After that the pipe was lifted
//    upward and the grain material flowed onto a cylindrical tray (200mm diameter with 22.5 mm high
//    edges) until the grain overflowed and formed a pile (with a base of grain ...)"
//
// Walls (all triangle meshes, docs/walls_and_motion.md): the tray (disc at z = 0 with its rim), the
// pipe standing on the tray floor, centred on the z axis, lifted by a `steady` motion that starts once
// the fill has settled (`start_time`), and a floor `floor_depth` below the tray that catches what
// overflows (so it comes to rest instead of falling for ever). The grain is poured into the pipe from
// above: the pipe's mesh is `fill_column` taller than `pipe_length` so that the loose rain fits; the
// poured grain settles well below `pipe_length` (the run checks this), so the extra length never
// touches grain and only makes the filling possible. Every dimension is a parameter.
#include <cstdint>
#include <string>

namespace grainscale::studies {

struct AorRig {
  double pipe_diameter = 0.100;     // m (report)
  double pipe_length = 0.300;       // m (report)
  double tray_diameter = 0.200;     // m (report)
  double tray_rim_height = 0.0225;  // m (report)
  double lift_speed = 0.05;         // m/s (not in the report; an assumption, see docs/aor_calibration.md)
  double fill_column = 0.1;         // m of pipe above pipe_length, for pouring only
  double floor_depth = 0.1;         // m below the tray floor
  std::string wall_material = "perspex";
  int segments = 48;                // polygon sides of the pipe and tray
};

/// The grain: clumps of a shape file (scaled by the scenario's scale factor) or spheres.
struct AorGrain {
  std::string material = "barley";  // name in the materials file
  std::string shape;                // shape file (made absolute in the scenario); empty: spheres
  double diameter = 0;              // m at run size (spheres only)
  double diameter_spread = 0;       // spheres only
  double particle_mass = 0;         // kg per clump at run size; 0: the material's density
  double mass = 0;                  // kg poured into the pipe
  double pour_rate = 2.0;           // kg/s
};

struct AorTiming {
  double step_fraction = 0.2;  // of the Rayleigh time
  double pour_interval = 0.005;  // s between pour insertions
  double settle_fill = 0.4;    // s between the planned end of the pour and the earliest lift
  double fill_rest_speed = 0.02;  // m/s: the lift waits until 95 % of the fill is slower than this
  double max_settle = 3.0;     // s the pile may take to come to rest after the pipe has cleared it
  double rest_speed = 0.005;   // m/s: the pile is at rest when 95 % of its grains are slower than this
};

struct AorCase {
  std::string name = "aor";
  std::uint64_t seed = 1;
  std::string materials_file;  // made absolute in the scenario
  double scale_factor = 1;
  std::string rolling_model = "constant_torque";
  double max_overlap = 0.3;
  AorRig rig;
  AorGrain grain;
  AorTiming timing;
};

/// When things happen in the scenario (s simulated).
struct AorSchedule {
  double pour_end = 0;    // planned: mass / rate
  double lift_start = 0;  // pour_end + the longest fall + settle_fill: the earliest lift; the study
                          // loop lifts later if the fill is still moving, and rewrites the scenario
  double end_time = 0;    // lift_start + the time to lift the whole pipe clear + max_settle (an upper
                          // bound; the study loop ends earlier once the pile is at rest)
};

/// With `lift_start` > 0, the lift begins then instead of at the earliest time.
AorSchedule aor_schedule(const AorCase& c, double lift_start = 0);

/// The scenario file's text (docs/scenario.md); `output_directory` goes into its output block.
/// `lift_start` > 0: the pipe's motion starts then (the time a run actually lifted: the pipe is at
/// rest until its lift, so the scenario with the actual time repeats the run exactly).
std::string aor_scenario_yaml(const AorCase& c, const std::string& output_directory, double lift_start = 0);

/// Mass of one particle at run size (kg): particle_mass, or the material density times the scaled
/// clump's volume (overlaps counted once) or the mean sphere's volume.
double aor_particle_mass(const AorCase& c);

}  // namespace grainscale::studies
