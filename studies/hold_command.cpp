#include "studies/hold_command.hpp"

#include <cstdio>
#include <iostream>

#include "dem/input_error.hpp"
#include "studies/hold_output.hpp"
#include "studies/hold_run.hpp"
#include "studies/hold_settings.hpp"

namespace grainscale::studies {

int hold_command(const std::vector<std::string>& positional, const std::string& out) {
  if (positional.size() != 1) throw InputError("usage: grainscale hold SETTINGS.yaml [--out DIR]");
  HoldSettings s = load_hold_settings(positional[0]);
  if (!out.empty()) s.output_folder = out;
  std::cerr << "[hold] " << s.name << ": " << s.length << " m x " << s.depth << " m, filled to " << s.fill_height
            << " m; motion " << s.motion->describe() << "; " << s.t_end << " s in cycles of " << s.chunk << " s\n";
  std::unique_ptr<HoldModel> model;
  const HoldResult r = run_hold(s, model, &std::cerr);
  const HoldFiles f = write_hold_output(s, *model, r);
  std::printf("hold run in %.3g s (%ld resolved cycles of %.3g s%s); closure steps %ld, chaff steps %ld\n",
              r.wall_seconds, r.resolved_chunks, s.chunk, r.averaged.back() ? ", then the cycle-averaged model" : "",
              r.closure_steps, r.chaff_steps);
  if (r.averaged.back()) {
    std::printf("averaged model (%s): %ld steps in %.3g s (stiffest cell rate %.3g /s)\n", r.averaged_integrator.c_str(),
                r.averaged_steps, r.averaged_wall_seconds, r.averaged_max_rate);
  }
  std::printf("chaff %.6g -> %.6g m^2 (relative change %.2g); c in [%.4g, %.4g]\n", r.chaff_initial, r.chaff_final,
              r.chaff_initial > 0 ? (r.chaff_final - r.chaff_initial) / r.chaff_initial : 0.0, r.c_min, r.c_max);
  std::printf("share of chaff in the top %.3g m within %.3g m of the ends: left %.4g, right %.4g\n", s.top_layer,
              s.end_zone, f.left_fraction, f.right_fraction);
  std::printf("spear (%.3g m) finds dirty grain (> %.3g x initial) at:", s.spear_depth, s.dirty_factor);
  if (f.dirty_from.empty()) std::printf(" nowhere");
  for (std::size_t k = 0; k < f.dirty_from.size(); ++k) std::printf(" [%.3g, %.3g] m", f.dirty_from[k], f.dirty_to[k]);
  std::printf("\noutput: %s\n", f.folder.c_str());
  return 0;
}

}  // namespace grainscale::studies
