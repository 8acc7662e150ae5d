#pragma once
// Natural cubic spline through (t_i, y_i): C2, so a tabulated motion has continuous velocity and
// acceleration. Second derivatives M_i from the tridiagonal system (Press et al., Numerical Recipes,
// 3rd ed., Sec. 3.3, eq. 3.3.7) with M_0 = M_{n-1} = 0; on [t_i, t_i+1], with h = t_i+1 - t_i,
// a = (t_i+1 - t)/h, b = 1 - a:
//   y = a y_i + b y_i+1 + ((a^3 - a) M_i + (b^3 - b) M_i+1) h^2 / 6            (eq. 3.3.3)
#include <vector>

namespace grainscale::dem {

class CubicSpline {
 public:
  CubicSpline() = default;
  /// t strictly increasing, at least two points (two points give a straight line).
  CubicSpline(std::vector<double> t, std::vector<double> y);
  /// Value and first and second derivatives at t (t within [front, back]; clamped outside).
  void evaluate(double t, double& y, double& dy, double& ddy) const;

 private:
  std::vector<double> t_, y_, m_;
};

}  // namespace grainscale::dem
