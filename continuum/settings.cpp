#include "continuum/settings.hpp"

#include <algorithm>
#include <filesystem>
#include <functional>

#include "continuum/analytic_flows.hpp"
#include "continuum/depth_averaged.hpp"
#include "continuum/gridded_flow.hpp"
#include "continuum/initial_from_fields.hpp"
#include "continuum/phase_resolved_flow.hpp"
#include "continuum/term_registry.hpp"
#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::continuum {

namespace {

void read_grid(YamlMap m, ContinuumSettings& s) {
  s.length = m.number("length", Range::positive());
  s.nx = static_cast<int>(m.integer("nx", 1, 100000));
  s.nz = static_cast<int>(m.integer("nz", 1, 10000));
  // Each bound alone admits 1e9 cells (tens of GB and hours per step): cap the product too.
  constexpr long kMaxCells = 4'000'000;
  if (static_cast<long>(s.nx) * s.nz > kMaxCells) {
    throw InputError(m.where("nz") + ": nx * nz = " + std::to_string(static_cast<long>(s.nx) * s.nz) +
                     " cells; at most " + std::to_string(kMaxCells) + " (a 2-D bed needs far fewer)");
  }
  if (m.has("depth") && m.has("surface")) {
    throw InputError(m.where("depth") + ": give either 'depth' (flat bed) or 'surface' (nx + 1 heights), not both");
  }
  if (!m.has("depth") && !m.has("surface")) {
    (void)m.number_or("depth", 0.0);  // neither: the surface comes from the flow file (checked later)
  } else if (m.has("depth")) {
    s.surface.assign(static_cast<std::size_t>(s.nx) + 1, m.number("depth", Range::positive()));
  } else {
    s.surface = m.numbers_or_empty("surface", static_cast<std::size_t>(s.nx) + 1, static_cast<std::size_t>(s.nx) + 1,
                                   {0, 1e9, true, false});
  }
  m.finish();
}

void read_flow(YamlMap m, ContinuumSettings& s) {
  s.flow.type = m.choice("type", {"cellular", "uniform_shear", "file", "sloshing"});
  if (s.flow.type == "sloshing") {
    if (s.surface.empty() || std::adjacent_find(s.surface.begin(), s.surface.end(), std::not_equal_to<>()) != s.surface.end()) {
      throw InputError(m.where("type") + ": flow type 'sloshing' needs a flat bed at rest: give grid.depth");
    }
    s.flow.amplitude = m.number("amplitude", {0, 0.9 * s.surface.front(), true, true});
    s.flow.period = m.number("period", Range::positive());
    s.flow.mode = static_cast<int>(m.integer_or("mode", 1, 1, 1000));
    s.flow.exponent = m.number_or("exponent", 2.0, {1, 10, true, true});
    if (s.flow.exponent > 1 && s.flow.exponent < 2) {
      throw InputError(m.where("exponent") + ": must be 1 or in [2, 10] (the shear rate σ^(p−2) is singular between)");
    }
    s.flow.cell = m.number_or("cell", 0.0);
    s.flow.background_shear = m.number_or("background_shear", 0.0, Range::non_negative());
  } else if (s.flow.type == "cellular") {
    s.flow.amplitude = m.number("amplitude");
    s.flow.background_shear = m.number_or("background_shear", 0.0, Range::non_negative());
  } else if (s.flow.type == "uniform_shear") {
    s.flow.shear_rate = m.number("shear_rate", Range::non_negative());
  } else {
    s.flow.file = resolve_beside(s.source_file, m.string("file"));
    if (!std::filesystem::exists(s.flow.file)) throw InputError(m.where("file") + ": cannot find '" + s.flow.file + "'");
    if (m.has("period")) {
      // Phase-resolved: every phase-averaged frame, interpolated in phase.
      if (m.has("frame")) throw InputError(m.where("frame") + ": give either 'frame' (one field) or 'period' (all phases), not both");
      s.flow.phase_resolved = true;
      s.flow.period = m.number("period", Range::positive());
      s.flow.t0 = m.number_or("t0", 0.0);
      s.flow.moving_surface = m.choice_or("surface", "moving", {"moving", "fixed"}) == "moving";
    } else {
      s.flow.frame = static_cast<int>(m.integer_or("frame", -1, -1000000, 1000000));  // coarse-grained files: which frame
    }
    if (m.choice_or("mobility", "shear_rate", {"shear_rate", "temperature"}) == "temperature") {
      if (s.flow.phase_resolved) throw InputError(m.where("mobility") + ": 'temperature' needs a single frame (no 'period')");
      s.flow.temperature_diameter = m.number("diameter", Range::closed(1e-5, 1.0));
    }
    if (m.choice_or("flux", "velocity", {"velocity", "volume"}) == "volume") {
      if (s.flow.phase_resolved) throw InputError(m.where("flux") + ": 'volume' needs a single frame (no 'period')");
      s.flow.volume_flux = true;
    }
  }
  m.finish();
}

void read_initial(YamlMap m, ContinuumSettings& s) {
  s.initial.type = m.choice("type", {"uniform", "layers", "file"});
  if (s.initial.type == "uniform") {
    s.initial.value = m.number("value", Range::closed(0, 1));
  } else if (s.initial.type == "file") {
    s.initial.file = resolve_beside(s.source_file, m.string("file"));
    if (!std::filesystem::exists(s.initial.file)) throw InputError(m.where("file") + ": cannot find '" + s.initial.file + "'");
    s.initial.frame = static_cast<int>(m.integer_or("frame", 0, -1000000, 1000000));
    s.initial.min_solid_fraction = m.number_or("min_solid_fraction", 0.3, Range::closed(0, 1));
  } else {
    s.initial.below = m.number("below", Range::closed(0, 1));
    s.initial.above = m.number("above", Range::closed(0, 1));
    s.initial.split = m.number("split", Range::closed(0, 1));
  }
  m.finish();
}

void read_time(YamlMap m, ContinuumSettings& s) {
  s.t_end = m.number("end", Range::positive());
  s.outputs = static_cast<int>(m.integer_or("outputs", 10, 1, 100000));
  s.stops = m.numbers_or_empty("stops", 0, 100000, {0, s.t_end, true, true});
  m.finish();
}

void read_integrator(YamlMap m, ContinuumSettings& s) {
  s.integrator.method = m.choice_or("method", "cvode", integrator_names());
  s.integrator.rtol = m.number_or("rtol", 1e-6, {0, 1, true, true});
  s.integrator.atol = m.number_or("atol", 1e-9, Range::positive());
  s.integrator.cfl = m.number_or("cfl", 0.4, {0, 1, true, false});
  s.integrator.max_dt = m.number_or("max_dt", 0.0, Range::non_negative());
  m.finish();
}

}  // namespace

ContinuumSettings load_continuum_settings(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  ContinuumSettings s;
  s.source_file = file;
  if (auto m = root.optional_map("model")) {
    const std::string type = m->choice_or("type", "resolved", {"resolved", "depth_averaged"});
    s.closure = type == "depth_averaged" ? Closure::depth_averaged : Closure::resolved;
    if (auto c = m->optional_map("cycle_average")) {
      if (s.closure != Closure::depth_averaged) {
        throw InputError(m->where("cycle_average") + ": cycle averaging is for model type depth_averaged");
      }
      s.cycle_period = c->number("period", Range::positive());
      s.cycle_phases = static_cast<int>(c->integer_or("phases", 16, 1, 10000));
      c->finish();
    }
    m->finish();
  }
  read_grid(root.map("grid"), s);
  read_flow(root.map("flow"), s);
  {
    // Each term's mapping is kept as a node (with its line numbers) and read by the registry.
    const YAML::Node raw = YAML::LoadFile(file)["terms"];
    YamlMap terms = root.map("terms");
    for (const std::string& name : terms.keys()) {
      (void)terms.map(name);  // must be a mapping; its keys are checked by build_model below
      s.terms.emplace_back(name, raw[name]);
    }
    if (s.terms.empty()) throw InputError(root.where("terms") + ": no terms given");
  }
  read_initial(root.map("initial"), s);
  read_time(root.map("time"), s);
  if (auto m = root.optional_map("integrator")) read_integrator(*m, s);
  if (auto m = root.optional_map("observation")) {
    s.kappa = m->number("kappa", Range::positive());
    s.delta = m->number("delta", Range::positive());
    m->finish();
  }
  {
    YamlMap out = root.map("output");
    s.output_folder = resolve_beside(file, out.string("folder"));
    s.slice_width = out.number_or("slice_width", 0.05, Range::positive());
    out.finish();
  }
  root.finish();
  if (s.surface.empty()) {
    if (s.flow.type != "file") throw InputError(file + ": key 'grid': give 'depth' or 'surface' (or a flow file)");
    if (s.flow.phase_resolved) {
      const PhaseResolvedFlow flow =
          PhaseResolvedFlow::load(s.flow.file, s.length, s.flow.period, s.flow.t0, s.flow.moving_surface);
      for (int f = 0; f <= s.nx; ++f) s.surface.push_back(flow.surface_at(s.length * f / s.nx, 0.0));
    } else {
      const GriddedFlow flow = GriddedFlow::load(s.flow.file, s.length, s.flow.frame, s.flow.temperature_diameter, s.flow.volume_flux);
      for (int f = 0; f <= s.nx; ++f) s.surface.push_back(flow.surface_height(s.length * f / s.nx));
    }
  } else if (s.flow.type == "file" && s.flow.phase_resolved && s.flow.moving_surface) {
    throw InputError(file + ": key 'grid': with a moving surface from phase-resolved fields the surface comes from the file; "
                     "leave out 'depth' and 'surface' (or set flow.surface: fixed)");
  }
  (void)build_model(s);  // term names, parameters and the flow file are checked now, not mid-run
  return s;
}

std::shared_ptr<const Flow> build_flow(const ContinuumSettings& s, const Grid& grid) {
  if (s.flow.type == "uniform_shear") return std::make_shared<UniformShear>(s.flow.shear_rate);
  if (s.flow.type == "file" && s.flow.phase_resolved) {
    return std::make_shared<PhaseResolvedFlow>(
        PhaseResolvedFlow::load(s.flow.file, s.length, s.flow.period, s.flow.t0, s.flow.moving_surface));
  }
  if (s.flow.type == "file") return std::make_shared<GriddedFlow>(GriddedFlow::load(s.flow.file, s.length, s.flow.frame, s.flow.temperature_diameter, s.flow.volume_flux));
  if (s.flow.type == "sloshing") {
    SloshingFlow::Shape shape;
    shape.length = s.length;
    shape.depth = s.surface.front();
    shape.amplitude = s.flow.amplitude;
    shape.mode = s.flow.mode;
    shape.period = s.flow.period;
    shape.exponent = s.flow.exponent;
    shape.cell = s.flow.cell;
    shape.background_shear = s.flow.background_shear;
    return std::make_shared<SloshingFlow>(shape);
  }
  // The cell's ψ vanishes on the grid's own (piecewise-linear) surface.
  std::function<double(double)> h = [grid](double x) {
    const double u = std::clamp(x / grid.dx(), 0.0, static_cast<double>(grid.nx()));
    const int f = std::min(static_cast<int>(u), grid.nx() - 1);
    return grid.h_node(f) + (u - f) * (grid.h_node(f + 1) - grid.h_node(f));
  };
  return std::make_shared<CellularFlow>(s.flow.amplitude, s.length, h, s.flow.background_shear);
}

Model build_model(const ContinuumSettings& s) {
  Grid grid(s.length, s.nx, s.nz, s.surface);
  auto flow = build_flow(s, grid);
  if (flow->moving_surface()) {
    // The grid starts on the flow's own surface at t = 0.
    std::vector<double> nodes;
    for (int f = 0; f <= s.nx; ++f) nodes.push_back(flow->surface_height(grid.x_face(f), 0.0));
    grid = Grid(s.length, s.nx, s.nz, nodes);
  }
  Model model(grid, flow, s.closure);
  if (s.cycle_phases > 0) model.set_cycle_average(s.cycle_period, s.cycle_phases);
  for (const auto& [name, node] : s.terms) {
    if (s.closure == Closure::depth_averaged && !DepthAveraged::supports(name)) {
      throw InputError(s.source_file + ": key 'terms." + name + "': model type depth_averaged has no form of this term (allowed: " +
                       DepthAveraged::supported_terms() + ")");
    }
    YamlMap params(node, s.source_file, "terms." + name);
    model.add_term(make_term(name, params));
  }
  return model;
}

std::vector<double> initial_field(const ContinuumSettings& s, const Grid& g) {
  if (s.initial.type == "file") return initial_from_cg_frame(s.initial.file, s.initial.frame, s.initial.min_solid_fraction, g);
  std::vector<double> c(g.cells(), s.initial.value);
  if (s.initial.type == "layers") {
    for (int i = 0; i < g.nx(); ++i) {
      for (int k = 0; k < g.nz(); ++k) c[g.index(i, k)] = g.sigma_centre(k) < s.initial.split ? s.initial.below : s.initial.above;
    }
  }
  return c;
}

std::vector<double> output_times(const ContinuumSettings& s) {
  std::vector<double> t;
  for (int j = 1; j <= s.outputs; ++j) t.push_back(s.t_end * j / s.outputs);
  return t;
}

}  // namespace grainscale::continuum
