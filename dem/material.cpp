#include "dem/material.hpp"

#include "dem/input_error.hpp"
#include "dem/yaml_map.hpp"

namespace grainscale::dem {

int MaterialTable::add(const Material& m) {
  for (const auto& e : materials_) {
    if (e.name == m.name) throw InputError("material '" + m.name + "' is defined twice");
  }
  const int n = size();
  std::vector<PairProperties> grown((n + 1) * (n + 1));
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) grown[a * (n + 1) + b] = pairs_[a * n + b];
  pairs_ = std::move(grown);
  materials_.push_back(m);
  return n;
}

void MaterialTable::set_pair(int a, int b, const PairProperties& p) {
  PairProperties q = p;
  q.defined = true;
  pairs_[a * size() + b] = q;
  pairs_[b * size() + a] = q;
}

int MaterialTable::index(const std::string& name, const std::string& context) const {
  for (int i = 0; i < size(); ++i) {
    if (materials_[i].name == name) return i;
  }
  std::string known;
  for (const auto& m : materials_) known += (known.empty() ? "" : ", ") + m.name;
  throw InputError((context.empty() ? "" : context + ": ") + "unknown material '" + name + "' (materials in " +
                   source_ + ": " + known + ")");
}

const PairProperties& MaterialTable::pair(int a, int b) const {
  const PairProperties& p = pairs_[a * size() + b];
  if (!p.defined) {
    throw InputError(source_ + ": no interaction properties for the pair '" + materials_[a].name + "-" +
                     materials_[b].name + "'; add it under 'pairs:'");
  }
  return p;
}

MaterialTable MaterialTable::load(const std::string& file) {
  YamlMap root = YamlMap::load_file(file);
  MaterialTable t;
  t.source_ = file;

  YamlMap mats = root.map("materials");
  for (const std::string& name : mats.keys()) {
    if (name.find('-') != std::string::npos) {
      throw InputError(mats.where(name) + ": material names may not contain '-' (it separates pair names)");
    }
    YamlMap m = mats.map(name);
    Material mat;
    mat.name = name;
    mat.density = m.number("density", {0, 1e5, true, false});
    mat.shear_modulus = m.number("shear_modulus", Range::positive());
    // Poisson's ratio of an isotropic elastic solid lies in (-1, 0.5); 0.5 (incompressible) makes
    // the Hertz reduced modulus singular for the Mindlin tangential stiffness ratio.
    mat.poisson_ratio = m.number("poisson_ratio", {-1, 0.5, true, true});
    m.finish();
    t.add(mat);
  }
  if (t.size() == 0) throw InputError(root.where("materials") + " lists no materials");

  YamlMap pairs = root.map("pairs");
  for (const std::string& key : pairs.keys()) {
    const auto dash = key.find('-');
    if (dash == std::string::npos || key.find('-', dash + 1) != std::string::npos) {
      throw InputError(pairs.where(key) + ": pair names are 'materialA-materialB'");
    }
    const int a = t.index(key.substr(0, dash), pairs.where(key));
    const int b = t.index(key.substr(dash + 1), pairs.where(key));
    if (t.pairs_[a * t.size() + b].defined) throw InputError(pairs.where(key) + ": pair defined twice");
    YamlMap p = pairs.map(key);
    PairProperties pp;
    pp.restitution = p.number("restitution", {0, 1, true, false});
    pp.friction = p.number("friction", {0, 10, false, false});
    pp.rolling_friction = p.number("rolling_friction", {0, 10, false, false});
    p.finish();
    t.set_pair(a, b, pp);
  }
  root.finish();
  return t;
}

}  // namespace grainscale::dem
