// Private: chi-square tails for the standardised residual scores of the
// outlier test (estimation.cpp) and the contact episodes (setup_checks.cpp).
#pragma once

#include <cmath>

namespace massid::detail {

// Chi-square with k (even) degrees of freedom (a sample's k standardised
// residuals): P(X > x) = exp(-x/2) sum_{j < k/2} (x/2)^j / j!; for k = 6,
// exp(-x/2) (1 + x/2 + x^2/8).
inline double chi2_survival(double x, int k) {
  double term = 1.0, sum = 0.0;
  for (int j = 0; j < k / 2; ++j) {
    sum += term;
    term *= x / 2 / (j + 1);
  }
  return std::exp(-x / 2) * sum;
}

// The score d = sqrt(X) that a clean sample exceeds with probability p.
inline double chi_quantile(double p, int k) {
  double lo = 0.0, hi = 2000.0;  // survival(2000) underflows to 0
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_survival(mid, k) > p ? lo : hi) = mid;
  }
  return std::sqrt(0.5 * (lo + hi));
}

}  // namespace massid::detail
