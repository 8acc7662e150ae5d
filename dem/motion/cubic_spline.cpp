#include "dem/motion/cubic_spline.hpp"

#include <algorithm>
#include <cassert>

namespace grainscale::dem {

CubicSpline::CubicSpline(std::vector<double> t, std::vector<double> y) : t_(std::move(t)), y_(std::move(y)) {
  const std::size_t n = t_.size();
  assert(n >= 2 && y_.size() == n);
  m_.assign(n, 0.0);
  if (n < 3) return;
  // Thomas algorithm for the interior second derivatives.
  std::vector<double> c(n, 0.0), d(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
    const double a = h0 / 6, b = (h0 + h1) / 3, cc = h1 / 6;
    const double r = (y_[i + 1] - y_[i]) / h1 - (y_[i] - y_[i - 1]) / h0;
    const double denom = b - a * c[i - 1];
    c[i] = cc / denom;
    d[i] = (r - a * d[i - 1]) / denom;
  }
  for (std::size_t i = n - 2; i >= 1; --i) m_[i] = d[i] - c[i] * m_[i + 1];
}

void CubicSpline::evaluate(double t, double& y, double& dy, double& ddy) const {
  const double tc = std::clamp(t, t_.front(), t_.back());
  std::size_t i = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), tc) - t_.begin());
  i = std::clamp<std::size_t>(i, 1, t_.size() - 1) - 1;
  const double h = t_[i + 1] - t_[i];
  const double a = (t_[i + 1] - tc) / h, b = 1 - a;
  y = a * y_[i] + b * y_[i + 1] + ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * h * h / 6;
  dy = (y_[i + 1] - y_[i]) / h - (3 * a * a - 1) / 6 * h * m_[i] + (3 * b * b - 1) / 6 * h * m_[i + 1];
  ddy = a * m_[i] + b * m_[i + 1];
}

}  // namespace grainscale::dem
