#include "coarsegrain/cg_settings.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::cg {

const char* name(Averaging a) {
  switch (a) {
    case Averaging::snapshot: return "snapshot";
    case Averaging::window: return "window";
    case Averaging::phase: return "phase";
    case Averaging::cycles: return "cycles";
  }
  return "?";
}

namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<SnapshotEntry> snapshot_dir(YamlMap& y, const std::string& file) {
  const std::string dir = resolve_beside(file, y.string("snapshot_dir"));
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(y.where("snapshot_dir") + ": '" + dir + "' is not a directory");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file() && e.path().extension() == ".h5") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());  // snap_000001.h5, ...: name order is time order
  if (files.empty()) throw InputError(y.where("snapshot_dir") + ": no *.h5 files in '" + dir + "'");
  std::vector<SnapshotEntry> out;
  for (auto& f : files) out.push_back({f, kNaN});
  return out;
}

}  // namespace

CgSettings load_cg_settings(const std::string& file) {
  YamlMap y = YamlMap::load_file(file);
  CgSettings s;
  s.source = file;

  if (y.has("snapshots") == y.has("snapshot_dir")) {
    throw InputError(file + ": give exactly one of 'snapshots' (a list of {path, phase}) and 'snapshot_dir'");
  }
  if (y.has("snapshots")) {
    for (YamlMap& e : y.list_of_maps("snapshots")) {
      s.snapshots.push_back({resolve_beside(file, e.string("path")), e.number_or("phase", kNaN)});
      e.finish();
    }
    if (s.snapshots.empty()) throw InputError(y.where("snapshots") + " is empty; list at least one snapshot");
  } else {
    s.snapshots = snapshot_dir(y, file);
  }

  YamlMap c = y.map("container");
  s.container_wall = c.string_or("wall", "");
  s.lo = c.vec3("lo");
  s.hi = c.vec3("hi");
  for (int a = 0; a < 3; ++a) {
    if (!(s.hi[a] > s.lo[a])) throw InputError(c.where("hi") + " must exceed 'lo' in every component (the grid box)");
  }
  c.finish();

  YamlMap g = y.map("grid");
  s.dimension = static_cast<int>(g.integer("dimension", 1, 3));
  const std::vector<double> cells = g.numbers_or_empty("cells", 3, 3, Range::closed(1, 100000));
  if (cells.empty()) throw InputError(g.where("cells") + ": missing; give [nx, ny, nz] (averaged axes are ignored)");
  for (int a = 0; a < 3; ++a) {
    const double n = cells[static_cast<std::size_t>(a)];
    if (n != std::floor(n)) throw InputError(g.where("cells") + " must be whole numbers");
    s.cells[static_cast<std::size_t>(a)] = static_cast<int>(n);
  }
  g.finish();

  YamlMap k = y.map("kernel");
  s.kernel = k.choice_or("type", "gaussian", {"gaussian", "lucy"}) == "lucy" ? KernelType::lucy : KernelType::gaussian;
  s.boundary = k.choice_or("boundary", "reflect", {"reflect", "renormalise"}) == "reflect" ? Boundary::reflect : Boundary::renormalise;
  s.width_diameters = k.number("width", {0, 100, true, false});
  s.true_diameter = k.number_or("diameter", 0, {0, 1, true, false});
  s.diameter_species = k.string_or("diameter_of", "");
  k.finish();

  YamlMap sp = y.map("species");
  for (const std::string& n : sp.keys()) {
    YamlMap m = sp.map(n);
    if (m.boolean_or("chaff", false)) s.chaff.push_back(n);
    if (m.has("density")) s.density[n] = m.number("density", Range::positive());
    m.finish();
  }
  sp.finish();
  if (s.chaff.empty()) throw InputError(y.where("species") + ": mark at least one species 'chaff: true'");

  if (auto a = y.optional_map("averaging")) {
    const std::string mode = a->choice_or("mode", "snapshot", {"snapshot", "window", "phase", "cycles"});
    s.averaging = mode == "window"   ? Averaging::window
                  : mode == "phase"  ? Averaging::phase
                  : mode == "cycles" ? Averaging::cycles
                                     : Averaging::snapshot;
    s.phase_bins = static_cast<int>(a->integer_or("phase_bins", 8, 1, 1000));
    s.period = a->number_or("period", 0, Range::non_negative());
    s.t0 = a->number_or("t0", 0);
    s.from = a->number_or("from", s.from);
    s.to = a->number_or("to", s.to);
    if (!(s.to > s.from)) throw InputError(a->where("to") + ": must be later than 'from'");
    if (s.averaging == Averaging::cycles && !(s.period > 0)) {
      throw InputError(a->where("period") + ": averaging by cycles needs the motion's period (s), > 0");
    }
    if (s.averaging == Averaging::phase && !(s.period > 0) && s.container_wall.empty()) {
      for (const auto& e : s.snapshots) {
        if (std::isnan(e.phase)) {
          throw InputError(a->where("period") + ": phase averaging needs 'period' (s), a 'phase' per snapshot, or a moving container wall (its recorded phase)");
        }
      }
    }
    a->finish();
  }

  if (auto su = y.optional_map("surface")) {
    s.surface.surface_fraction = su->number_or("fraction", 0.5, {0, 1, true, true});
    s.surface.bulk_volume_fraction = su->number_or("bulk_volume_fraction", 0, Range::closed(0, 1));
    su->finish();
  }

  if (auto me = y.optional_map("measures")) {
    s.slice_width = me->number_or("slice_width", 0.05, Range::positive());
    s.end_length = me->number_or("end_length", 0.1, Range::positive());
    s.top_view.pixel = me->number_or("pixel", 0.001, {0, 0.1, true, false});
    s.top_view.layer_thickness = me->number_or("layer_thickness", 0, Range::non_negative());
    if (!(2 * s.end_length <= s.hi.x - s.lo.x)) {
      throw InputError(me->where("end_length") + ": the two end zones must fit in the container length (2 x end_length <= hi.x - lo.x)");
    }
    me->finish();
  } else if (!(2 * s.end_length <= s.hi.x - s.lo.x)) {
    throw InputError(file + ": the container is shorter than the two default 0.1 m end zones; set measures.end_length");
  }

  s.output_dir = resolve_beside(file, y.string("output"));
  y.finish();
  return s;
}

}  // namespace grainscale::cg
