#include "continuum/phase_resolved_flow.hpp"

#include <algorithm>
#include <cmath>

#include "dem/input_error.hpp"

namespace grainscale::continuum {

PhaseResolvedFlow::PhaseResolvedFlow(std::vector<Phase> phases, double period, double t0, bool moving)
    : phases_(std::move(phases)), period_(period), t0_(t0), moving_(moving) {
  if (phases_.size() < 2) throw InputError("phase-resolved flow: need at least two phases");
  if (!(period_ > 0) || !std::isfinite(period_)) throw InputError("phase-resolved flow: the period must be > 0");
  for (auto& p : phases_) p.phase -= std::floor(p.phase);
  std::sort(phases_.begin(), phases_.end(), [](const Phase& a, const Phase& b) { return a.phase < b.phase; });
  for (std::size_t j = 0; j + 1 < phases_.size(); ++j) {
    if (phases_[j + 1].phase - phases_[j].phase < 1e-9) throw InputError("phase-resolved flow: two fields at the same phase");
  }
  // Equal bed areas: every phase's surface scaled to the mean area (P1).
  const double L = phases_.front().field.length();
  double mean = 0;
  for (const auto& p : phases_) mean += p.field.surface_integral(L) / phases_.size();
  for (auto& p : phases_) {
    const double factor = mean / p.field.surface_integral(L);
    area_correction_ = std::max(area_correction_, std::abs(factor - 1));
    p.field = p.field.with_surface_scaled(factor);
  }
}

PhaseResolvedFlow PhaseResolvedFlow::load(const std::string& file, double length, double period, double t0, bool moving) {
  const auto frames = GriddedFlow::phase_frames(file);
  if (frames.size() < 2) {
    throw InputError(file + ": phase-resolved flow needs at least two phase-averaged frames (grainscale cg with averaging mode " +
                     "'phase'), found " + std::to_string(frames.size()));
  }
  std::vector<Phase> phases;
  for (const auto& [frame, phase] : frames) phases.push_back({phase, GriddedFlow::load(file, length, frame)});
  return PhaseResolvedFlow(std::move(phases), period, t0, moving);
}

PhaseResolvedFlow::Bracket PhaseResolvedFlow::bracket(double t) const {
  const double cycles = (t - t0_) / period_;
  const double phi = cycles - std::floor(cycles);
  const int n = static_cast<int>(phases_.size());
  // The last bin at or before φ (periodic: before the first bin is the last one, a cycle earlier).
  int a = n - 1;
  for (int j = 0; j < n; ++j) {
    if (phases_[j].phase <= phi) a = j;
  }
  const int b = (a + 1) % n, before = (a + n - 1) % n, after = (b + 1) % n;
  // Phase positions unwrapped around p_a: p_before < p_a ≤ φ < p_b < p_after.
  const double pa = phases_[a].phase;
  const double at = phi < pa ? phi + 1 : phi;
  double pb = phases_[b].phase;
  if (pb <= pa) pb += 1;
  double pm = phases_[before].phase;
  while (pm >= pa) pm -= 1;
  double pp = phases_[after].phase;
  while (pp <= pb) pp += 1;
  // Cubic Hermite on [p_a, p_b] with Catmull–Rom slopes m_a = (f_b − f_before) / (p_b − p_before),
  // m_b = (f_after − f_a) / (p_after − p_a), written as weights on the four values.
  const double D = pb - pa, s = (at - pa) / D, ds_dt = 1 / (D * period_);
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s, h01 = -2 * s * s * s + 3 * s * s,
               h11 = s * s * s - s * s;
  const double d00 = 6 * s * s - 6 * s, d10 = 3 * s * s - 4 * s + 1, d01 = -6 * s * s + 6 * s, d11 = 3 * s * s - 2 * s;
  const double ra = D / (pb - pm), rb = D / (pp - pa);
  Bracket k{{before, a, b, after},
            {-h10 * ra, h00 - h11 * rb, h01 + h10 * ra, h11 * rb},
            {-d10 * ra * ds_dt, (d00 - d11 * rb) * ds_dt, (d01 + d10 * ra) * ds_dt, d11 * rb * ds_dt}};
  return k;
}

double PhaseResolvedFlow::mean_surface(double x) const {
  double h = 0;
  for (const auto& p : phases_) h += p.field.surface_height(x);
  return h / phases_.size();
}

double PhaseResolvedFlow::surface_at(double x, double t) const {
  if (!moving_) return mean_surface(x);
  const Bracket k = bracket(t);
  double h = 0;
  for (int j = 0; j < 4; ++j) h += k.w[j] * phases_[k.phase[j]].field.surface_height(x);
  return h;
}

double PhaseResolvedFlow::surface_height(double x, double t) const { return surface_at(x, t); }

double PhaseResolvedFlow::surface_flux(double x, double t) const {
  if (!moving_) return 0;
  const Bracket k = bracket(t);
  double q = 0;
  for (int j = 0; j < 4; ++j) q -= k.w_rate[j] * phases_[k.phase[j]].field.surface_integral(x);
  return q;
}

double PhaseResolvedFlow::stream_function(double x, double z, double t) const {
  const Bracket k = bracket(t);
  const double sigma = z / surface_at(x, t);
  double psi = 0;
  for (int j = 0; j < 4; ++j) {
    const GriddedFlow& f = phases_[k.phase[j]].field;
    psi += k.w[j] * f.stream_function(x, sigma * f.surface_height(x), t);
  }
  if (moving_) psi += surface_flux(x, t) * std::clamp(sigma, 0.0, 1.0);
  return psi;
}

double PhaseResolvedFlow::shear_rate(double x, double z, double t) const {
  const Bracket k = bracket(t);
  const double sigma = z / surface_at(x, t);
  double rate = 0;
  for (int j = 0; j < 4; ++j) {
    const GriddedFlow& f = phases_[k.phase[j]].field;
    rate += k.w[j] * f.shear_rate(x, sigma * f.surface_height(x), t);
  }
  return std::max(rate, 0.0);
}

}  // namespace grainscale::continuum
