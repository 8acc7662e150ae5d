#pragma once
// A small bed with everything switched on, shared by the conservation, bounds and integrator tests:
// 0.4 m long, 0.1 m deep on average with a sloping surface (h = H(1 + ε cos πx/L), ε = 0.2), one convection cell (|u| ≈ 1.5 cm/s),
// segregation, shear and background diffusion.
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "continuum/analytic_flows.hpp"
#include "continuum/model.hpp"
#include "continuum/terms/advection.hpp"
#include "continuum/terms/background_diffusion.hpp"
#include "continuum/terms/segregation.hpp"
#include "continuum/terms/shear_diffusion.hpp"
#include "manufactured.hpp"

namespace grainscale::continuum::test {

inline Model full_bed(int nx, int nz, Limiter limiter, double S = 1e-3, double C = 0.5, double D0 = 1e-6,
                      double surface_slope = 0.2) {
  constexpr double pi = std::numbers::pi;
  const double L = 0.4, H = 0.1;
  auto h = [=](double x) { return H * (1 + surface_slope * std::cos(pi * x / L)); };
  auto flow = std::make_shared<CellularFlow>(5e-4, L, h, 0.05);
  Model model(terrain_grid(L, nx, nz, h), flow);
  model.add_term(std::make_unique<Advection>(limiter));
  model.add_term(std::make_unique<Segregation>(S, limiter));
  model.add_term(std::make_unique<ShearDiffusion>(C, 4e-3));
  model.add_term(std::make_unique<BackgroundDiffusion>(D0));
  return model;
}

/// c = 1 in a block (x in [0.1, 0.2] m, σ in [0.2, 0.5]), 0 elsewhere: discontinuous in both directions.
inline std::vector<double> block(const Grid& g) {
  std::vector<double> c(g.cells(), 0.0);
  for (int i = 0; i < g.nx(); ++i) {
    for (int k = 0; k < g.nz(); ++k) {
      const bool in = g.x_centre(i) > 0.1 && g.x_centre(i) < 0.2 && g.sigma_centre(k) > 0.2 && g.sigma_centre(k) < 0.5;
      c[g.index(i, k)] = in ? 1.0 : 0.0;
    }
  }
  return c;
}

}  // namespace grainscale::continuum::test
