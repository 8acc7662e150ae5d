#include "continuum/terms/effective_gravity.hpp"

#include <algorithm>
#include <cmath>

namespace grainscale::continuum {

namespace {
constexpr double kGravity = 9.81;

/// sgn(e) (|e| − μ)⁺: the part of a slope above the bed's static friction.
double excess(double e, double mu) { return std::copysign(std::max(0.0, std::abs(e) - mu), e); }
}  // namespace

std::pair<double, double> effective_gravity_anomaly(const CycleMotion& m, double x, double z, int samples) {
  const double rx = x - m.axis_x, rz = z - m.axis_z;
  if (!(m.alpha2 > 0) || !(m.omega2 > 0)) return {m.omega2 * rx / kGravity, m.omega2 * rz / kGravity};
  const double w = std::sqrt(m.alpha2 / m.omega2), A = std::sqrt(2 * m.omega2) / w;
  double ax = 0, normal = 0, tilt_normal = 0;
  for (int j = 0; j < samples; ++j) {
    const double phase = 2 * M_PI * (j + 0.5) / samples;
    const double th = A * std::sin(phase), thd = A * w * std::cos(phase), thdd = -w * w * th;
    const double gx = kGravity * std::sin(th) - thdd * rz + thd * thd * rx;  // (G1)
    const double gz = -kGravity * std::cos(th) + thdd * rx + thd * thd * rz;
    const double e = gz < 0 ? std::clamp(gx / -gz, -kMaxSlope, kMaxSlope) : std::copysign(kMaxSlope, gx);
    ax += excess(e, m.mu) - excess(std::tan(th), m.mu);
    normal += -gz / kGravity;
    tilt_normal += std::cos(th);
  }
  return {ax / samples, -(normal - tilt_normal) / samples};
}

AnomalyTable::AnomalyTable(const CycleMotion& m, double x_lo, double x_hi, double z_lo, double z_hi, int nx, int nz)
    : motion_(m), x_lo_(x_lo), x_hi_(x_hi), z_lo_(z_lo), z_hi_(z_hi), nx_(nx), nz_(nz), ax_(nx * nz), az_(nx * nz) {
  for (int i = 0; i < nx; ++i) {
    for (int k = 0; k < nz; ++k) {
      const auto [ax, az] = effective_gravity_anomaly(m, x_lo + (x_hi - x_lo) * i / (nx - 1), z_lo + (z_hi - z_lo) * k / (nz - 1));
      ax_[i * nz + k] = ax;
      az_[i * nz + k] = az;
    }
  }
}

bool AnomalyTable::covers(double x_lo, double x_hi, double z_lo, double z_hi) const {
  return !ax_.empty() && x_lo >= x_lo_ && x_hi <= x_hi_ && z_lo >= z_lo_ && z_hi <= z_hi_;
}

std::pair<double, double> AnomalyTable::at(double x, double z) const {
  const double u = std::clamp((x - x_lo_) / (x_hi_ - x_lo_), 0.0, 1.0) * (nx_ - 1);
  const double v = std::clamp((z - z_lo_) / (z_hi_ - z_lo_), 0.0, 1.0) * (nz_ - 1);
  const int i = std::min(static_cast<int>(u), nx_ - 2), k = std::min(static_cast<int>(v), nz_ - 2);
  const double fu = u - i, fv = v - k;
  auto lerp = [&](const std::vector<double>& t) {
    return (1 - fu) * ((1 - fv) * t[i * nz_ + k] + fv * t[i * nz_ + k + 1]) +
           fu * ((1 - fv) * t[(i + 1) * nz_ + k] + fv * t[(i + 1) * nz_ + k + 1]);
  };
  return {lerp(ax_), lerp(az_)};
}

}  // namespace grainscale::continuum
