#include "studies/hold_settings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "continuum/closure/bed_friction.hpp"
#include "continuum/term_registry.hpp"
#include "dem/input_error.hpp"
#include "dem/motion/motion_from_yaml.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::studies {

HoldSettings load_hold_settings(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  HoldSettings s;
  s.source_file = file;
  s.name = root.string("name");
  {
    YamlMap c = root.map("container");
    s.length = c.number("length", Range{0, 1e4, true, false});
    s.depth = c.number("depth", Range{0, 1e3, true, false});
    if (c.has("fill") == c.has("fill_height")) {
      throw InputError(c.where("fill") + ": give exactly one of 'fill' (fraction of the depth, (0, 1]) or 'fill_height' (m)");
    }
    s.fill_height = c.has("fill") ? s.depth * c.number("fill", Range{0, 1, true, false})
                                  : c.number("fill_height", Range{0, s.depth, true, false});
    s.decked = c.boolean_or("decked", false);
    s.nx = static_cast<int>(c.integer_or("nx", 100, 4, 100000));
    s.direction = c.choice_or("direction", "longitudinal", {"longitudinal", "transverse"});
    const std::vector<double> pivot = c.numbers_or_empty("pivot", 2, 2);
    if (!pivot.empty()) s.pivot_x = pivot[0], s.pivot_z = pivot[1];
    // Distance between the side walls across the section: their friction μ_w a/W (side_wall_friction.hpp);
    // absent: a 2-D section without side-wall friction.
    if (c.has("width")) s.width = c.number("width", Range{0, 1e4, true, false});
    c.finish();
  }
  {
    YamlMap t = root.map("time");
    s.t_end = t.number("end", Range{0, 1e9, true, false});
    s.outputs = static_cast<int>(t.integer_or("outputs", 24, 1, 100000));
    const double chunk = t.number_or("chunk", 0.0, Range::non_negative());
    const std::string resolve = t.string_or("resolve", "all");  // "all" or a number of cycles
    s.average_chunks = t.integer_or("average_cycles", 10, 1, 1000000);
    // The motion needs the end time (a record must cover the run).
    s.motion = dem::motion_from_yaml(root.map("motion"), s.t_end);
    s.chunk = chunk > 0 ? chunk : s.motion->period();
    if (!(s.chunk > 0)) {
      throw InputError(t.where("chunk") + ": the motion is not periodic; give the chunk length in s (> 0)");
    }
    const long total = static_cast<long>(std::ceil(s.t_end / s.chunk - 1e-9));
    if (resolve == "all") {
      s.resolved_chunks = total;
    } else {
      char* end = nullptr;
      const long n = std::strtol(resolve.c_str(), &end, 10);
      if (*end != '\0' || n < 1) throw InputError(t.where("resolve") + ": 'all' or a number of cycles >= 1");
      s.resolved_chunks = std::min(n, total);
    }
    if (s.resolved_chunks < total && s.average_chunks > s.resolved_chunks) {
      throw InputError(t.where("average_cycles") + ": must not exceed the resolved cycles (" +
                       std::to_string(s.resolved_chunks) + ")");
    }
    t.finish();
  }
  s.friction = continuum::closure::bed_friction_from_yaml(root.map("material"));
  s.friction.side_walls.width = s.width;
  {
    YamlMap ch = root.map("chaff");
    s.window = std::min(ch.number_or("window", 1.0, Range{0, 1e3, true, false}), s.fill_height);
    s.nz = static_cast<int>(ch.integer_or("nz", 20, 1, 10000));
    s.chaff_initial = ch.number("initial", Range::closed(0, 1));
    const YAML::Node raw = YAML::LoadFile(file)["chaff"]["terms"];
    YamlMap terms = ch.map("terms");
    for (const std::string& n : terms.keys()) {
      (void)terms.map(n);
      s.terms.emplace_back(n, raw[n]);
      YamlMap params(raw[n], file, "chaff.terms." + n);
      (void)continuum::make_term(n, params);  // names, keys and ranges checked now, not mid-run
    }
    if (auto im = ch.optional_map("integrator")) {
      s.integrator.method = im->choice_or("method", "ssp_rk3", {"ssp_rk3", "cvode"});
      s.integrator.cfl = im->number_or("cfl", 0.4, Range{0, 1, true, false});
      s.integrator.rtol = im->number_or("rtol", 1e-6, Range::positive());
      s.integrator.atol = im->number_or("atol", 1e-9, Range::positive());
      s.integrator.max_dt = im->number_or("max_dt", 0.0, Range::non_negative());
      im->finish();
    }
    if (auto im = ch.optional_map("averaged_integrator")) {
      s.averaged_integrator.method = im->choice_or("method", "cvode", {"cvode", "ssp_rk3"});
      s.averaged_integrator.cfl = im->number_or("cfl", 0.4, Range{0, 1, true, false});
      s.averaged_integrator.rtol = im->number_or("rtol", 1e-6, Range{0, 0.1, true, false});
      s.averaged_integrator.atol = im->number_or("atol", 1e-9, Range{0, 0.1, true, false});
      im->finish();
    }
    ch.finish();
  }
  // The flow changes within a cycle faster than an explicit step sized at its start can see.
  if (s.integrator.max_dt == 0) s.integrator.max_dt = s.chunk / 100;
  {
    YamlMap o = root.map("output");
    s.output_folder = resolve_beside(file, o.string("folder"));
    s.top_layer = o.number_or("top_layer", 0.1, Range{0, 1e3, true, false});
    s.end_zone = o.number_or("end_zone", std::min(1.0, 0.125 * s.length), Range{0, s.length / 2, true, false});
    s.spear_depth = o.number_or("spear_depth", 1.6, Range{0, 1e3, true, false});
    s.dirty_factor = o.number_or("dirty_factor", 2.0, Range{1, 1e6, true, false});
    o.finish();
  }
  root.finish();
  return s;
}

}  // namespace grainscale::studies
