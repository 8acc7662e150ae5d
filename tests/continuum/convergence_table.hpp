#pragma once
// A convergence table as deal.II step-7 prints it: cells, error, observed order log2(e_coarse/e_fine).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace grainscale::continuum::test {

struct ConvergenceTable {
  explicit ConvergenceTable(std::string t) : title(std::move(t)) {}
  std::string title;
  std::vector<int> resolution;
  std::vector<double> error;

  void add(int n, double e) {
    resolution.push_back(n);
    error.push_back(e);
  }
  /// Observed order between the last two rows (resolutions doubling).
  double last_rate() const { return std::log(error[error.size() - 2] / error.back()) / std::log(2.0); }
  std::string str() const {
    std::string s = title + "\n      n        L2 error    rate\n";
    char line[96];
    for (std::size_t j = 0; j < error.size(); ++j) {
      if (j == 0) {
        std::snprintf(line, sizeof line, "  %5d  %14.4e       -\n", resolution[j], error[j]);
      } else {
        std::snprintf(line, sizeof line, "  %5d  %14.4e  %6.2f\n", resolution[j], error[j],
                      std::log(error[j - 1] / error[j]) / std::log(2.0));
      }
      s += line;
    }
    return s;
  }
};

}  // namespace grainscale::continuum::test
