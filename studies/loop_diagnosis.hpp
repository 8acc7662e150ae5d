#pragma once
// Diagnosis of a fit's residual (`grainscale loop`, step 2; docs/loop.md). The normalised residual
// r = (model − data)/σ of every observation is split by where and when it lies, to point at the
// kind of effect the model lacks:
//  - symmetric vs antisymmetric about the container centre (pairs of mirrored cells/columns at one
//    time; energies of (a ± b)/2 add up to a² + b²): a missing drift to both ends is symmetric, a
//    lever arm or a tilt bias antisymmetric;
//  - surface layer vs bulk, near the end walls vs interior (RMS of r in each);
//  - cycle mean vs 1st and 2nd harmonics of the motion (nested least squares per location in time,
//    energies explained by a constant, then + cos/sin φ, then + cos/sin 2φ, φ = 2π t/T);
//  - dependence on the model's own c (mean r in quantile bins of c, and their correlation);
//  - whiteness: pooled Box–Pierce portmanteau Q = Σ_k N_k ρ_k² ~ χ²(h) (Box & Pierce 1970; the
//    Ljung–Box family) and the Wald–Wolfowitz runs test on the signs about the median, each with
//    the residual ordered in x (along each layer at each time) and in t (at each location).
//    White if no p-value is below alpha / (number of tests) (Bonferroni).
#include <optional>
#include <string>
#include <vector>

#include "continuum/grid.hpp"
#include "studies/fit_observations.hpp"
#include "studies/observed_fit.hpp"

namespace grainscale::studies {

/// One observation's residual with where and when it is.
struct ResidualPoint {
  bool coverage = false;
  std::size_t time = 0;  // index into the observation times
  double t = 0, x = 0, z = 0;
  int column = 0, layer = 0;  // layer: the cell's (fields), nz for coverage
  double r = 0;               // (model − data) / sigma
  double error = 0;           // model − data (data units)
  double model_c = 0;         // the model's c there (coverage: its top cell)
};

std::vector<ResidualPoint> residual_points(const continuum::Grid& grid, const Observations& data, const Prediction& p);

struct SeriesTest {
  std::string order;       // "x" or "t"
  int series = 0, points = 0, lags = 0;
  std::vector<double> autocorrelation;  // ρ_1..ρ_h (pooled)
  std::vector<int> pairs;               // N_k
  double q = 0, q_p = 1;                // Box–Pierce (pooled) and its p-value
  double runs = 0, runs_expected = 0, runs_z = 0, runs_p = 1;
};

struct DiagnosisSettings {
  double period = 0;          // s, motion cycle; 0: no harmonic split
  double surface_layer = 0;   // m, top layer counted as "surface"
  double wall_band = 0;       // m, from each end wall counted as "near wall"
  int max_lag = 8;
  double alpha = 0.01;
};

struct Group {
  std::string name;
  int count = 0;
  double rms = 0, mean = 0;
};

struct Diagnosis {
  int points = 0;
  double rms = 0;
  // Symmetry about x = L/2.
  int mirrored_pairs = 0;
  double symmetric_energy = 0, antisymmetric_energy = 0;  // fractions of the paired energy
  std::vector<Group> regions;  // surface, bulk, coverage, near wall, interior
  // Harmonics of the motion (fractions of the energy of the locations used).
  bool harmonics_resolved = false;
  std::string harmonics_note;
  int harmonic_locations = 0;
  double mean_energy = 0, first_harmonic = 0, second_harmonic = 0, rest_energy = 0;
  // Dependence on the model's c.
  std::vector<double> c_bin_centre, c_bin_mean_r;
  std::vector<int> c_bin_count;
  double correlation_with_c = 0;
  // Whiteness.
  std::vector<SeriesTest> tests;
  bool tested = false;  // enough points in series for the whiteness tests
  bool white = true;    // meaningful only when tested
  std::string verdict;
};

Diagnosis diagnose(const continuum::Grid& grid, const std::vector<ResidualPoint>& points, const DiagnosisSettings& s);

/// The portmanteau and runs tests on series (each in its order); exposed for tests.
SeriesTest whiteness(const std::string& order, const std::vector<std::vector<double>>& series, int max_lag);

}  // namespace grainscale::studies
