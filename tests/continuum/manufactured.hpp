#pragma once
// Manufactured solutions (Roache; deal.II step-7): choose c_exact, put the residual of the PDE
//   ∂c/∂t + ∇·(u c) + ∂z[S γ̇ c(1−c)] − ∇·(D∇c) = s,   D = K γ̇ + D0,
// back in as a source s, and measure how fast the discrete solution approaches c_exact. The
// derivatives in s are nested central differences with a step far below the grid spacing, so s is
// exact to ~1e-8, well below the discretisation errors measured.
#include <cmath>
#include <functional>

#include "continuum/grid.hpp"

namespace grainscale::continuum::test {

using Field = std::function<double(double, double, double)>;  // (x, z, t)

struct Manufactured {
  Field c;           // exact solution
  Field psi;         // stream function (zero if no advection)
  Field shear;       // γ̇
  double S = 0;      // segregation length
  double K = 0;      // D = K γ̇ + D0
  double D0 = 0;
  double delta = 2e-5;  // inner difference step [m]; the outer one is 10x larger

  double source(double x, double z, double t) const {
    const double e = delta;
    auto u = [&](double X, double Z) { return psi ? (psi(X, Z + e, t) - psi(X, Z - e, t)) / (2 * e) : 0.0; };
    auto w = [&](double X, double Z) { return psi ? -(psi(X + e, Z, t) - psi(X - e, Z, t)) / (2 * e) : 0.0; };
    auto D = [&](double X, double Z) { return K * shear(X, Z, t) + D0; };
    auto cx = [&](double X, double Z) { return (c(X + e, Z, t) - c(X - e, Z, t)) / (2 * e); };
    auto cz = [&](double X, double Z) { return (c(X, Z + e, t) - c(X, Z - e, t)) / (2 * e); };
    auto Fx = [&](double X, double Z) { return u(X, Z) * c(X, Z, t) - D(X, Z) * cx(X, Z); };
    auto Fz = [&](double X, double Z) {
      const double cc = c(X, Z, t);
      return w(X, Z) * cc + S * shear(X, Z, t) * cc * (1 - cc) - D(X, Z) * cz(X, Z);
    };
    const double E = 10 * e;  // outer step: keeps the nested differences out of round-off
    const double div = (Fx(x + E, z) - Fx(x - E, z)) / (2 * E) + (Fz(x, z + E) - Fz(x, z - E)) / (2 * E);
    const double dt = 1e-5;
    const double ct = (c(x, z, t + dt) - c(x, z, t - dt)) / (2 * dt);
    return ct + div;
  }
};

/// Area-weighted L2 error of cell values against c_exact at the cell centres, over the bed area.
inline double l2_error(const Grid& g, const std::vector<double>& c, const Field& exact, double t) {
  double sum = 0;
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) {
      const double d = c[g.index(i, k)] - exact(g.x_centre(i), g.z_centre(i, k), t);
      sum += g.area(i, k) * d * d;
    }
  }
  return std::sqrt(sum / g.total_area());
}

/// Cell values of f at the centres.
inline std::vector<double> sample(const Grid& g, const Field& f, double t) {
  std::vector<double> c(g.cells());
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) c[g.index(i, k)] = f(g.x_centre(i), g.z_centre(i, k), t);
  }
  return c;
}

/// Piecewise-linear grid surface from a smooth h(x) sampled at the column faces.
inline Grid terrain_grid(double length, int nx, int nz, const std::function<double(double)>& h) {
  std::vector<double> nodes(nx + 1);
  for (int f = 0; f <= nx; ++f) nodes[f] = h(f * length / nx);
  return Grid(length, nx, nz, nodes);
}

}  // namespace grainscale::continuum::test
