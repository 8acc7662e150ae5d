#include "dem/motion/tabulated_motion.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <vector>

#include "dem/input_error.hpp"
#include "dem/motion/euler_angles.hpp"

namespace grainscale::dem {

namespace {
const char* const kColumns[7] = {"t_s", "roll_deg", "pitch_deg", "yaw_deg", "surge_m", "sway_m", "heave_m"};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream s(line);
  while (std::getline(s, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r"), e = cell.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? std::string() : cell.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}
}  // namespace

TabulatedMotion TabulatedMotion::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the motion record");
  TabulatedMotion m;
  m.file_ = path;
  std::array<std::vector<double>, 7> col;
  std::string line;
  int line_no = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    const std::vector<std::string> cells = split(line);
    const std::string where = path + ":" + std::to_string(line_no);
    if (!header) {
      std::string expected;
      for (int k = 0; k < 7; ++k) {
        if (k) expected += ',';
        expected += kColumns[k];
      }
      bool ok = cells.size() == 7;
      for (int k = 0; ok && k < 7; ++k) ok = cells[k] == kColumns[k];
      if (!ok) throw InputError(where + ": the header must be exactly '" + expected + "' (units in the names)");
      header = true;
      continue;
    }
    if (cells.size() != 7) {
      throw InputError(where + ": expected 7 values, found " + std::to_string(cells.size()));
    }
    for (int k = 0; k < 7; ++k) {
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(cells[k].c_str(), &end);
      if (cells[k].empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
        throw InputError(where + ": column '" + kColumns[k] + "': '" + cells[k] + "' is not a finite number");
      }
      if (k == 0 && !col[0].empty() && !(v > col[0].back())) {
        throw InputError(where + ": column 't_s': time must increase strictly (" + cells[0] + " after " +
                         std::to_string(col[0].back()) + ")");
      }
      if (k >= 1 && k <= 3 && std::abs(v) > 360) {
        throw InputError(where + ": column '" + kColumns[k] + "': " + cells[k] + " is outside [-360, 360] degrees");
      }
      col[k].push_back(k >= 1 && k <= 3 ? v * std::numbers::pi / 180 : v);
    }
  }
  if (!header) throw InputError(path + ": empty motion record (no header line)");
  if (col[0].size() < 2) throw InputError(path + ": a motion record needs at least two rows, found " + std::to_string(col[0].size()));
  m.t0_ = col[0].front();
  m.t1_ = col[0].back();
  m.rows_ = col[0].size();
  for (int k = 0; k < 6; ++k) m.dof_[k] = CubicSpline(col[0], col[k + 1]);
  return m;
}

RigidMotionState TabulatedMotion::at(double t) const {
  double q[6], dq[6], ddq[6];
  const bool outside = t < t0_ || t > t1_;
  for (int k = 0; k < 6; ++k) {
    dof_[k].evaluate(t, q[k], dq[k], ddq[k]);
    if (outside) dq[k] = ddq[k] = 0;  // held at the end value
  }
  RigidMotionState s;
  set_rotation({{q[0], q[1], q[2]}, {dq[0], dq[1], dq[2]}, {ddq[0], ddq[1], ddq[2]}}, s);
  s.displacement = {q[3], q[4], q[5]};
  s.velocity = {dq[3], dq[4], dq[5]};
  s.acceleration = {ddq[3], ddq[4], ddq[5]};
  return s;
}

std::string TabulatedMotion::describe() const {
  std::ostringstream o;
  o << "recorded motion " << file_ << " (" << rows_ << " rows, t = " << t0_ << " to " << t1_ << " s, cubic splines)";
  return o.str();
}

}  // namespace grainscale::dem
