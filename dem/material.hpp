#pragma once
// Materials and material-pair interaction properties, read from a materials YAML file:
//
//   materials:
//     barley:  {density: 1380, shear_modulus: 2.6e6, poisson_ratio: 0.3}
//     perspex: {density: 1190, shear_modulus: 7.97e8, poisson_ratio: 0.38}
//   pairs:
//     barley-barley:  {restitution: 0.5, friction: 0.35, rolling_friction: 0.08}
//     barley-perspex: {restitution: 0.5, friction: 0.25, rolling_friction: 0.01}
//
// A shear modulus of .inf declares a rigid material (e.g. a steel plate in an impact benchmark).
#include <string>
#include <vector>

namespace grainscale::dem {

struct Material {
  std::string name;
  double density = 0;        // kg/m^3
  double shear_modulus = 0;  // Pa (may be +inf: rigid)
  double poisson_ratio = 0;  // -
  /// Young's modulus E = 2 G (1 + nu).
  double youngs_modulus() const { return 2.0 * shear_modulus * (1.0 + poisson_ratio); }
};

struct PairProperties {
  double restitution = 1;       // normal coefficient of restitution, (0, 1]
  double friction = 0;          // Coulomb sliding friction coefficient
  double rolling_friction = 0;  // rolling friction coefficient (dimensionless, EDEM convention)
  bool defined = false;
};

class MaterialTable {
 public:
  /// Load and validate; every error names the file, line, key and allowed range.
  static MaterialTable load(const std::string& file);

  int add(const Material& m);  // returns the material index
  void set_pair(int a, int b, const PairProperties& p);

  int size() const { return static_cast<int>(materials_.size()); }
  const Material& operator[](int i) const { return materials_[i]; }
  /// Index of the named material; throws InputError listing the known names.
  int index(const std::string& name, const std::string& context = "") const;
  /// Pair properties; throws InputError if the pair was never defined.
  const PairProperties& pair(int a, int b) const;
  bool has_pair(int a, int b) const { return pairs_[a * size() + b].defined; }
  const std::string& source() const { return source_; }

 private:
  std::vector<Material> materials_;
  std::vector<PairProperties> pairs_;  // size() x size(), symmetric
  std::string source_ = "(built in code)";
};

}  // namespace grainscale::dem
