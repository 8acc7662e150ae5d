#include "continuum/depth_averaged.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "continuum/model.hpp"
#include "continuum/terms/advection.hpp"

namespace grainscale::continuum {

namespace {

double logistic(double x) {
  if (x >= 0) return 1 / (1 + std::exp(-x));
  const double e = std::exp(x);
  return e / (1 + e);
}

constexpr int kMinSamples = 64;
constexpr double kMaxStep = 30;  // largest Λ increment per sample: beyond it the profile is a step anyway

}  // namespace

void equilibrium_profile(std::span<const double> Lambda, double theta, std::span<double> c, double* mu_guess) {
  const std::size_t n = Lambda.size();
  if (theta <= 0) {
    std::fill(c.begin(), c.end(), 0.0);
    return;
  }
  if (theta >= 1) {
    std::fill(c.begin(), c.end(), 1.0);
    return;
  }
  // mean_j logistic(Λ_j − μ) decreases in μ; with L = logit θ it is ≥ θ at μ = min Λ − L and
  // ≤ θ at μ = max Λ − L. Safeguarded Newton inside that bracket.
  const double L = std::log(theta / (1 - theta));
  const auto [mn, mx] = std::minmax_element(Lambda.begin(), Lambda.end());
  double lo = *mn - L, hi = *mx - L;
  auto mean = [&](double mu, double& slope) {
    double s = 0, d = 0;
    for (std::size_t j = 0; j < n; ++j) {
      const double v = logistic(Lambda[j] - mu);
      c[j] = v;
      s += v;
      d += v * (1 - v);
    }
    slope = -d / n;
    return s / n - theta;
  };
  double mu = mu_guess && *mu_guess > lo && *mu_guess < hi ? *mu_guess : 0.5 * (lo + hi), slope = 0;
  bool filled = false;  // c holds the profile at mu
  for (int it = 0; it < 200; ++it) {
    const double f = mean(mu, slope);
    filled = true;
    // Converged when the mean is θ to round-off (the sum of N terms carries ~N ε relative error).
    if (std::abs(f) <= 4 * std::numeric_limits<double>::epsilon() * theta) break;
    if (f > 0) lo = mu; else hi = mu;
    double next = slope < 0 ? mu - f / slope : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    // Converged when the next step is at round-off: keep the profile just computed.
    if (std::abs(next - mu) <= 4 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(mu))) break;
    mu = next;
    filled = false;
  }
  if (!filled) (void)mean(mu, slope);
  if (mu_guess) *mu_guess = mu;
}

DepthAveraged::Coefficients DepthAveraged::coefficients(const Model& m) {
  Coefficients k;
  if (m.has_term("segregation")) k.S = m.parameter("segregation.S");
  if (m.has_term("shear_diffusion")) {
    const double d = m.parameter("shear_diffusion.d");
    k.per_shear = m.parameter("shear_diffusion.C") * d * d;
  }
  if (m.has_term("background_diffusion")) k.D0 = m.parameter("background_diffusion.D0");
  if (m.has_term("advection")) {
    k.velocity_scale = m.parameter("advection.velocity_scale");
    if (const auto* a = dynamic_cast<const Advection*>(&m.term("advection"))) k.limiter = a->limiter();
  }
  return k;
}

bool DepthAveraged::supports(const std::string& name) {
  return name == "advection" || name == "segregation" || name == "shear_diffusion" || name == "background_diffusion";
}

std::string DepthAveraged::supported_terms() { return "advection, segregation, shear_diffusion, background_diffusion"; }

struct DepthAveraged::Cache {
  bool prepared = false;
  double time = 0;
  long stamp = 0;
  FaceCoefficients fine;          // on the (nx, N) grid: x-face volume fluxes and γ̇
  std::vector<double> col_shear;  // γ̇ at (x_i, σ_j h̄_i), [i * N + j]
  std::vector<double> mu;         // last μ per slot
  std::vector<double> lambda;     // Λ per slot [slot * N + j]
  std::vector<char> lambda_valid;
  double key[3] = {0, 0, 0};      // coefficients Λ was computed with
  long lambda_stamp = -1;
};

DepthAveraged::DepthAveraged(const Grid& grid)
    : nx_(grid.nx()), nsub_(std::max(1, (kMinSamples + grid.nz() - 1) / grid.nz())), samples_(grid.nz() * nsub_) {
  caches_.resize(1);
}

DepthAveraged::~DepthAveraged() = default;

void DepthAveraged::set_cycle_average(double period, int phases) {
  if (phases < 0 || (phases > 0 && !(period > 0))) throw std::invalid_argument("cycle average: need period > 0, phases >= 0");
  cycle_period_ = period;
  cycle_phases_ = phases;
  caches_.resize(1 + static_cast<std::size_t>(phases));
}

DepthAveraged::Cache& DepthAveraged::cache(std::size_t j) const {
  if (!caches_[j]) {
    caches_[j] = std::make_unique<Cache>();
    caches_[j]->mu.assign(3 * static_cast<std::size_t>(nx_ + 1), std::numeric_limits<double>::quiet_NaN());
  }
  return *caches_[j];
}

Grid DepthAveraged::grid_at(const Grid& g, const Flow& flow, double t) {
  if (!flow.moving_surface()) return g;
  std::vector<double> h(static_cast<std::size_t>(g.nx()) + 1);
  for (int f = 0; f <= g.nx(); ++f) h[f] = flow.surface_height(g.x_face(f), t);
  return Grid(g.length(), g.nx(), g.nz(), h);
}

void DepthAveraged::prepare(Cache& c, const Grid& g, const Flow& flow, double t) const {
  if (c.prepared && (flow.steady() || t == c.time)) return;
  const int N = samples_;
  const Grid fine(g.length(), g.nx(), N, g.surface_nodes(), g.column_depths());
  c.fine.update(fine, flow, t);
  c.col_shear.resize(static_cast<std::size_t>(g.nx()) * N);
  for (int i = 0; i < g.nx(); ++i) {
    for (int j = 0; j < N; ++j) {
      c.col_shear[static_cast<std::size_t>(i) * N + j] = flow.shear_rate(g.x_centre(i), (j + 0.5) / N * g.h_column(i), t);
    }
  }
  c.prepared = true;
  c.time = t;
  ++c.stamp;
}

void DepthAveraged::lambda(const Coefficients& k, const double* shear, double h, std::vector<double>& out) const {
  const int N = samples_;
  out.resize(N);
  const double dz = h / N;
  double cumulative = 0;
  for (int j = 0; j < N; ++j) {
    const double D = k.per_shear * shear[j] + k.D0;
    const double w = k.S * shear[j];
    double step = D > 0 ? w / D * dz : (w > 0 ? kMaxStep : (w < 0 ? -kMaxStep : 0.0));
    step = std::clamp(step, -kMaxStep, kMaxStep);
    out[j] = cumulative + 0.5 * step;
    cumulative += step;
  }
}

void DepthAveraged::profile(Cache& cache, const Coefficients& k, int slot, const double* shear, double h,
                            double theta, std::span<double> c) const {
  // Λ depends on the coefficients and the flow, not on the state: cached per slot.
  const std::size_t N = samples_;
  if (cache.lambda_valid.size() != cache.mu.size() || k.S != cache.key[0] || k.per_shear != cache.key[1] ||
      k.D0 != cache.key[2] || cache.stamp != cache.lambda_stamp) {
    cache.lambda_valid.assign(cache.mu.size(), 0);
    cache.lambda.resize(cache.mu.size() * N);
    cache.key[0] = k.S;
    cache.key[1] = k.per_shear;
    cache.key[2] = k.D0;
    cache.lambda_stamp = cache.stamp;
  }
  const auto s = static_cast<std::size_t>(slot);
  double* Lambda = &cache.lambda[s * N];
  if (!cache.lambda_valid[s]) {
    lambda(k, shear, h, scratch_lambda_);
    std::copy(scratch_lambda_.begin(), scratch_lambda_.end(), Lambda);
    cache.lambda_valid[s] = 1;
  }
  equilibrium_profile(std::span<const double>(Lambda, N), std::clamp(theta, 0.0, 1.0), c, &cache.mu[s]);
}

std::vector<double> DepthAveraged::inventory(const Grid& g, std::span<const double> c) const {
  std::vector<double> I(static_cast<std::size_t>(g.nx()), 0.0);
  for (int i = 0; i < g.nx(); ++i) {
    double s = 0;
    for (int k = 0; k < g.nz(); ++k) s += c[g.index(i, k)];
    I[i] = s * g.dsigma() * g.h_column(i);
  }
  return I;
}

std::vector<double> DepthAveraged::concentration(const Grid& g, const Flow& flow, double t, const Coefficients& k,
                                                 std::span<const double> I) const {
  Cache& cc = cache(0);
  prepare(cc, g, flow, t);
  const int N = samples_;
  std::vector<double> c(g.cells()), col(N);
  for (int i = 0; i < g.nx(); ++i) {
    profile(cc, k, 3 * i, &cc.col_shear[static_cast<std::size_t>(i) * N], g.h_column(i), I[i] / g.h_column(i), col);
    for (int kk = 0; kk < g.nz(); ++kk) {
      double s = 0;
      for (int j = kk * nsub_; j < (kk + 1) * nsub_; ++j) s += col[j];
      c[g.index(i, kk)] = s / nsub_;
    }
  }
  return c;
}

void DepthAveraged::fluxes(const Grid& g, const Flow& flow, double t, const Coefficients& k, std::span<const double> I,
                           std::vector<double>& F) const {
  if (cycle_phases_ == 0) {
    instantaneous_fluxes(cache(0), g, flow, t, k, I, F);
    return;
  }
  // (A3): the average over the phases of the cycle at fixed I; independent of t.
  F.assign(static_cast<std::size_t>(g.nx()) + 1, 0.0);
  for (int p = 0; p < cycle_phases_; ++p) {
    const double tp = (p + 0.5) / cycle_phases_ * cycle_period_;
    instantaneous_fluxes(cache(1 + p), grid_at(g, flow, tp), flow, tp, k, I, F_phase_);
    for (std::size_t f = 0; f < F.size(); ++f) F[f] += F_phase_[f] / cycle_phases_;
  }
}

void DepthAveraged::instantaneous_fluxes(Cache& cc, const Grid& g, const Flow& flow, double t, const Coefficients& k,
                                         std::span<const double> I, std::vector<double>& F) const {
  prepare(cc, g, flow, t);
  const int nx = g.nx(), N = samples_;
  const double dx = g.dx(), ds = 1.0 / N;
  F.assign(static_cast<std::size_t>(nx) + 1, 0.0);
  if (nx < 2) return;
  std::vector<double> theta(nx);
  for (int i = 0; i < nx; ++i) theta[i] = std::clamp(I[i] / g.h_column(i), 0.0, 1.0);
  col_c_.resize(static_cast<std::size_t>(nx) * N);
  for (int i = 0; i < nx; ++i) {
    profile(cc, k, 3 * i, &cc.col_shear[static_cast<std::size_t>(i) * N], g.h_column(i), theta[i],
            std::span<double>(&col_c_[static_cast<std::size_t>(i) * N], N));
  }
  auto col = [&](int i, int j) { return col_c_[static_cast<std::size_t>(i) * N + j]; };
  auto d_sigma = [&](int i, int j) {
    if (N == 1) return 0.0;
    if (j == 0) return (col(i, 1) - col(i, 0)) / ds;
    if (j == N - 1) return (col(i, j) - col(i, j - 1)) / ds;
    return (col(i, j + 1) - col(i, j - 1)) / (2 * ds);
  };
  // Limited slopes of θ (zero in the wall columns).
  std::vector<double> slope(nx, 0.0);
  if (k.limiter != Limiter::first_order) {
    for (int i = 1; i + 1 < nx; ++i) slope[i] = limited_slope(k.limiter, theta[i] - theta[i - 1], theta[i + 1] - theta[i]);
  }
  face_l_.resize(N);
  face_r_.resize(N);
  std::vector<double> face_shear(N);
  const Grid fine(g.length(), nx, N, g.surface_nodes(), g.column_depths());
  for (int f = 1; f < nx; ++f) {
    const double h = g.h_node(f), hx = g.slope_node(f);
    for (int j = 0; j < N; ++j) face_shear[j] = cc.fine.shear_x[x_face(fine, f, j)];
    double flux = 0;
    if (k.velocity_scale != 0) {
      const double* left = &col_c_[static_cast<std::size_t>(f - 1) * N];
      const double* right = &col_c_[static_cast<std::size_t>(f) * N];
      if (k.limiter != Limiter::first_order) {
        profile(cc, k, 3 * f + 1, face_shear.data(), h, theta[f - 1] + 0.5 * slope[f - 1], face_l_);
        profile(cc, k, 3 * f + 2, face_shear.data(), h, theta[f] - 0.5 * slope[f], face_r_);
        left = face_l_.data();
        right = face_r_.data();
      }
      for (int j = 0; j < N; ++j) {
        const double q = k.velocity_scale * cc.fine.volume_flux_x[x_face(fine, f, j)];
        flux += q > 0 ? q * left[j] : q * right[j];
      }
    }
    // Diffusion, (D1) on the N sample layers.
    for (int j = 0; j < N; ++j) {
      const double D = k.per_shear * face_shear[j] + k.D0;
      if (D == 0) continue;
      const double c_xi = (col(f, j) - col(f - 1, j)) / dx;
      const double cross = hx != 0 ? (j + 0.5) * ds * hx / h * 0.5 * (d_sigma(f - 1, j) + d_sigma(f, j)) : 0.0;
      flux -= D * h * ds * (c_xi - cross);
    }
    F[f] = flux;
  }
}

void DepthAveraged::rhs(const Grid& g, const Flow& flow, double t, const Coefficients& k, std::span<const double> I,
                        std::span<double> dIdt) const {
  fluxes(g, flow, t, k, I, F_base_);
  for (int i = 0; i < g.nx(); ++i) dIdt[i] = -(F_base_[i + 1] - F_base_[i]) / g.dx();
}

double DepthAveraged::max_rate(const Grid& g, const Flow& flow, double t, const Coefficients& k) const {
  if (cycle_phases_ == 0) return instantaneous_max_rate(cache(0), g, flow, t, k);
  double rate = 0;  // the average's bound is at most the largest phase's
  for (int p = 0; p < cycle_phases_; ++p) {
    const double tp = (p + 0.5) / cycle_phases_ * cycle_period_;
    rate = std::max(rate, instantaneous_max_rate(cache(1 + p), grid_at(g, flow, tp), flow, tp, k));
  }
  return rate;
}

double DepthAveraged::instantaneous_max_rate(Cache& cc, const Grid& g, const Flow& flow, double t,
                                             const Coefficients& k) const {
  // |∂F/∂I| ≤ max |u| over the face (the profile's samples are non-negative and average to θ, and
  // ∂c_j/∂I ≥ 0), and ≤ max D (1 + |h_x|) / dx for the dispersion: two faces per column.
  prepare(cc, g, flow, t);
  const int N = samples_;
  const Grid fine(g.length(), g.nx(), N, g.surface_nodes(), g.column_depths());
  double rate = 0;
  for (int f = 1; f < g.nx(); ++f) {
    const double h = g.h_node(f);
    double u = 0, D = 0;
    for (int j = 0; j < N; ++j) {
      u = std::max(u, std::abs(k.velocity_scale * cc.fine.volume_flux_x[x_face(fine, f, j)]) / (h / N));
      D = std::max(D, k.per_shear * cc.fine.shear_x[x_face(fine, f, j)] + k.D0);
    }
    rate = std::max(rate, 2 * (u / g.dx() + D * (1 + std::abs(g.slope_node(f))) / (g.dx() * g.dx())));
  }
  return rate;
}

void DepthAveraged::jacobian(const Grid& g, const Flow& flow, double t, const Coefficients& k,
                             std::span<const double> I, int b,
                             const std::function<void(std::size_t, std::size_t, double)>& add) const {
  // As conservative_jacobian.hpp: face f (columns L = f − 1, R = f) depends on columns L − 1 .. L + 2.
  const long n = g.nx();
  const long w = std::min<long>(2L * b + 1, n);
  std::vector<double> base;
  fluxes(g, flow, t, k, I, base);
  std::vector<double> Ip(I.begin(), I.end()), inc(n);
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  for (long j = 0; j < n; ++j) inc[j] = root_eps * std::max(std::abs(I[j]), 1e-3 * g.h_column(static_cast<int>(j)));
  for (long group = 0; group < w; ++group) {
    for (long j = group; j < n; j += w) Ip[j] = I[j] + inc[j];
    fluxes(g, flow, t, k, Ip, F_pert_);
    for (long j = group; j < n; j += w) Ip[j] = I[j];
    for (long f = 1; f < n; ++f) {
      const long L = f - 1, R = f;
      const long j = L - b + ((group - (L - b)) % w + w) % w;
      if (j < 0 || j >= n || j > L + b) continue;
      const double dF = (F_pert_[f] - base[f]) / inc[j];
      if (dF == 0) continue;
      if (std::abs(L - j) <= b) add(L, j, -dF / g.dx());
      if (std::abs(R - j) <= b) add(R, j, dF / g.dx());
    }
  }
}

}  // namespace grainscale::continuum
