#include "continuum/face_coefficients.hpp"

namespace grainscale::continuum {

double face_volume_flux(double psi_start, double psi_end) { return psi_end - psi_start; }

void FaceCoefficients::update(const Grid& g, const Flow& flow, double t) {
  const int nx = g.nx(), nz = g.nz();
  volume_flux_x.assign(x_face_count(g), 0.0);
  shear_x.assign(x_face_count(g), 0.0);
  volume_flux_s.assign(s_face_count(g), 0.0);
  shear_s.assign(s_face_count(g), 0.0);
  column_area_rate.assign(static_cast<std::size_t>(nx), 0.0);

  // ψ at the corners (x_f, σ_m h_f) of the grid; every face flux is a difference of two of them.
  std::vector<double> psi(static_cast<std::size_t>(nx + 1) * (nz + 1));
  auto corner = [&](int f, int m) -> double& { return psi[static_cast<std::size_t>(f) * (nz + 1) + m]; };
  for (int f = 0; f <= nx; ++f) {
    for (int m = 0; m <= nz; ++m) corner(f, m) = flow.stream_function(g.x_face(f), g.sigma_face(m) * g.h_node(f), t);
  }
  for (int f = 0; f <= nx; ++f) {
    for (int k = 0; k < nz; ++k) {
      // Through the vertical x-face, in +x: ∫ u dz = ∫ ∂ψ/∂z dz = ψ(top) − ψ(bottom).
      volume_flux_x[x_face(g, f, k)] = face_volume_flux(corner(f, k), corner(f, k + 1));
      shear_x[x_face(g, f, k)] = flow.shear_rate(g.x_face(f), g.sigma_centre(k) * g.h_node(f), t);
    }
  }
  for (int i = 0; i < nx; ++i) {
    for (int m = 0; m <= nz; ++m) {
      // Upward through z = σ_m h(x): ∫ (w − u dz/dx) dx = −∫ dψ along the face = ψ(left) − ψ(right).
      volume_flux_s[s_face(g, i, m)] = face_volume_flux(corner(i + 1, m), corner(i, m));
      shear_s[s_face(g, i, m)] = flow.shear_rate(g.x_centre(i), g.sigma_face(m) * g.h_column(i), t);
    }
  }
  if (!flow.moving_surface()) return;
  // (F1): the faces move with σ_m ȧ_i; the surface face (m = nz, σ = 1 exactly) gets Q_rel = 0.
  for (int i = 0; i < nx; ++i) {
    const double rate = corner(i, nz) - corner(i + 1, nz);
    column_area_rate[i] = rate;
    for (int m = 0; m <= nz; ++m) volume_flux_s[s_face(g, i, m)] -= (static_cast<double>(m) / nz) * rate;
  }
}

}  // namespace grainscale::continuum
