#include "continuum/closure/cycle_averaged_transport.hpp"

#include <algorithm>
#include <cmath>

#include "continuum/face_coefficients.hpp"

namespace grainscale::continuum::closure {

void CycleFluxSampler::sample(double t, const FaceFluxes& f, const std::vector<double>& c) {
  if (!have_last_) {
    last_f_ = f, last_c_ = c, t_last_ = t, have_last_ = true;
    sum_f_.x.assign(f.x.size(), 0.0), sum_f_.s.assign(f.s.size(), 0.0), sum_c_.assign(c.size(), 0.0);
    span_ = 0;
    return;
  }
  const double w = 0.5 * (t - t_last_);
  for (std::size_t k = 0; k < f.x.size(); ++k) sum_f_.x[k] += w * (f.x[k] + last_f_.x[k]);
  for (std::size_t k = 0; k < f.s.size(); ++k) sum_f_.s[k] += w * (f.s[k] + last_f_.s[k]);
  for (std::size_t k = 0; k < c.size(); ++k) sum_c_[k] += w * (c[k] + last_c_[k]);
  span_ += t - t_last_;
  last_f_ = f, last_c_ = c, t_last_ = t;
}

void CycleFluxSampler::end_cycle() {
  if (span_ <= 0) return;
  for (double& v : sum_f_.x) v /= span_;
  for (double& v : sum_f_.s) v /= span_;
  for (double& v : sum_c_) v /= span_;
  rows_f_.push_back(sum_f_);
  rows_c_.push_back(sum_c_);
  // The next cycle starts from this cycle's last sample.
  sum_f_.x.assign(sum_f_.x.size(), 0.0), sum_f_.s.assign(sum_f_.s.size(), 0.0), sum_c_.assign(sum_c_.size(), 0.0);
  span_ = 0;
}

namespace {

/// A face's cycle-mean difference c_R − c_L must exceed this fraction of its mean concentration
/// (rms over the cycles) for K to be fitted. Chosen from the full Handysize hold: below 1e-5 the
/// fitted K scattered over 5 decades (to 0.56 m²/s at b/a = 2e-8, against a median of 1e-7 and a
/// largest 2.5e-4 m²/s in the flowing surface layer, where b/a ~ 0.1).
constexpr double kMinResolvedDifference = 1e-5;

/// The drift's mobility in (A1): c̄ (1 − c̄) at the face's mean concentration.
double mobility(double cl, double cr) {
  const double m = 0.5 * (cl + cr);
  return m * (1 - m);
}

/// Least squares of y ≈ V a − K b; K ≥ |V|/2 afterwards. cc = Σ_j c̄_j², the scale b is resolved against.
void regress(const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& y, double cc,
             double& V, double& K) {
  double aa = 0, ab = 0, bb = 0, ay = 0, by = 0;
  for (std::size_t j = 0; j < y.size(); ++j) {
    aa += a[j] * a[j], ab += a[j] * b[j], bb += b[j] * b[j], ay += a[j] * y[j], by += b[j] * y[j];
  }
  const double det = aa * bb - ab * ab;
  // Over a few cycles c changes little, so a and b are nearly collinear and K is not identified:
  // then the drift alone (with the monotone minimum dispersion |V|/2, i.e. upwind). K is also not
  // identified where the difference across the face is unresolved (kMinResolvedDifference): there
  // y, a and b all drift slowly together over the averaged cycles and K fits that common trend
  // (the static core of the full Handysize hold: b/a ~ 1e-8 gave K = 0.56 m²/s, a rate of 90 /s).
  if (det > 1e-2 * (aa * bb) && det > 0 && bb > kMinResolvedDifference * kMinResolvedDifference * cc) {
    V = (bb * ay - ab * by) / det;
    K = (ab * ay - aa * by) / det;  // from V aa − K ab = ay, V ab − K bb = by
  } else {
    V = aa > 0 ? ay / aa : 0;
    K = 0;
  }
  K = std::max(K, 0.5 * std::abs(V));
}

}  // namespace

void CycleFluxSampler::fit(std::vector<double>& vx, std::vector<double>& kx, std::vector<double>& vs,
                           std::vector<double>& ks) const {
  const Grid& g = grid_;
  const int n = cycles();
  vx.assign(x_face_count(g), 0.0), kx.assign(x_face_count(g), 0.0);
  vs.assign(s_face_count(g), 0.0), ks.assign(s_face_count(g), 0.0);
  std::vector<double> a(n), b(n), y(n);
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const std::size_t L = g.index(f - 1, k), R = g.index(f, k), face = x_face(g, f, k);
      double cc = 0;
      for (int j = 0; j < n; ++j) {
        a[j] = mobility(rows_c_[j][L], rows_c_[j][R]), b[j] = rows_c_[j][R] - rows_c_[j][L], y[j] = rows_f_[j].x[face];
        cc += 0.25 * (rows_c_[j][L] + rows_c_[j][R]) * (rows_c_[j][L] + rows_c_[j][R]);
      }
      regress(a, b, y, cc, vx[face], kx[face]);
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const std::size_t L = g.index(i, m - 1), R = g.index(i, m), face = s_face(g, i, m);
      double cc = 0;
      for (int j = 0; j < n; ++j) {
        a[j] = mobility(rows_c_[j][L], rows_c_[j][R]), b[j] = rows_c_[j][R] - rows_c_[j][L], y[j] = rows_f_[j].s[face];
        cc += 0.25 * (rows_c_[j][L] + rows_c_[j][R]) * (rows_c_[j][L] + rows_c_[j][R]);
      }
      regress(a, b, y, cc, vs[face], ks[face]);
    }
  }
}

CycleAveragedTransport::CycleAveragedTransport(std::vector<double> vx, std::vector<double> kx, std::vector<double> vs,
                                               std::vector<double> ks)
    : FluxTerm("cycle_averaged_transport", {}), vx_(std::move(vx)), kx_(std::move(kx)), vs_(std::move(vs)), ks_(std::move(ks)) {}

void CycleAveragedTransport::add_fluxes(const TermContext& ctx, std::span<const double> c, FaceFluxes& out) const {
  const Grid& g = ctx.grid;
  for (int f = 1; f < g.nx(); ++f) {
    for (int k = 0; k < g.nz(); ++k) {
      const std::size_t face = x_face(g, f, k);
      const double cl = c[g.index(f - 1, k)], cr = c[g.index(f, k)];
      out.x[face] += vx_[face] * mobility(cl, cr) - kx_[face] * (cr - cl);  // (A1)
    }
  }
  for (int i = 0; i < g.nx(); ++i) {
    for (int m = 1; m < g.nz(); ++m) {
      const std::size_t face = s_face(g, i, m);
      const double cl = c[g.index(i, m - 1)], cr = c[g.index(i, m)];
      out.s[face] += vs_[face] * mobility(cl, cr) - ks_[face] * (cr - cl);
    }
  }
}

void CycleAveragedTransport::add_rate_bound(const TermContext& ctx, std::span<double> rate) const {
  const Grid& g = ctx.grid;
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) {
      double r = 0;
      if (i > 0) r += 0.5 * std::abs(vx_[x_face(g, i, k)]) + kx_[x_face(g, i, k)];
      if (i + 1 < g.nx()) r += 0.5 * std::abs(vx_[x_face(g, i + 1, k)]) + kx_[x_face(g, i + 1, k)];
      if (k > 0) r += 0.5 * std::abs(vs_[s_face(g, i, k)]) + ks_[s_face(g, i, k)];
      if (k + 1 < g.nz()) r += 0.5 * std::abs(vs_[s_face(g, i, k + 1)]) + ks_[s_face(g, i, k + 1)];
      rate[g.index(i, k)] += r / g.area(i, k);
    }
  }
}

}  // namespace grainscale::continuum::closure
