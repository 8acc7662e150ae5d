#include "dem/shape.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::dem {

Vec3 Shape::bounding_size() const {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& s : spheres) {
    lo = {std::min(lo.x, s.center.x - s.radius), std::min(lo.y, s.center.y - s.radius), std::min(lo.z, s.center.z - s.radius)};
    hi = {std::max(hi.x, s.center.x + s.radius), std::max(hi.y, s.center.y + s.radius), std::max(hi.z, s.center.z + s.radius)};
  }
  return hi - lo;
}

std::vector<double> Shape::sorted_dimensions() const {
  const Vec3 b = bounding_size();
  std::vector<double> d{b.x, b.y, b.z};
  std::sort(d.begin(), d.end(), std::greater<>());
  return d;
}

Shape load_shape(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  Shape s;
  s.name = root.string("name");
  s.source = root.string_or("source", "");
  const double unit = root.choice_or("length_unit", "m", {"m", "mm"}) == "mm" ? 1e-3 : 1.0;
  const std::vector<YamlMap> list = root.list_of_maps("spheres");
  if (list.empty() || list.size() > 1000) throw InputError(root.where("spheres") + " must list 1 to 1000 spheres");
  for (YamlMap m : list) {
    SphereComponent c;
    c.center = unit * m.vec3("center");
    c.radius = unit * m.number("radius", Range::positive());
    if (!std::isfinite(c.radius)) throw InputError(m.where("radius") + " must be finite");
    m.finish();
    s.spheres.push_back(c);
  }
  for (double d : root.numbers_or_empty("measured_size", 1, 3, Range::positive())) s.measured_size.push_back(unit * d);

  // One rigid piece: the overlap graph of the spheres must be connected.
  std::vector<int> group(s.spheres.size());
  for (std::size_t i = 0; i < group.size(); ++i) group[i] = static_cast<int>(i);
  std::function<int(int)> find = [&](int i) { return group[i] == i ? i : group[i] = find(group[i]); };
  for (std::size_t i = 0; i < s.spheres.size(); ++i)
    for (std::size_t j = i + 1; j < s.spheres.size(); ++j) {
      if (norm(s.spheres[i].center - s.spheres[j].center) < s.spheres[i].radius + s.spheres[j].radius) {
        group[find(static_cast<int>(i))] = find(static_cast<int>(j));
      }
    }
  for (std::size_t i = 1; i < s.spheres.size(); ++i) {
    if (find(static_cast<int>(i)) != find(0)) {
      std::ostringstream m;
      m << root.where("spheres") << ": sphere " << i << " does not overlap the rest; a shape must be one rigid piece of overlapping spheres";
      throw InputError(m.str());
    }
  }
  root.finish();
  return s;
}

}  // namespace grainscale::dem
