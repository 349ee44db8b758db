// Private: chi-square tails for the standardised residual scores of the
// outlier test (estimation.cpp) and the contact episodes (setup_checks.cpp).
#pragma once

#include <cmath>
#include <numbers>

namespace massid::detail {

// Chi-square with k degrees of freedom (a sample's k standardised residuals):
//   k even: P(X > x) = exp(-x/2) sum_{j < k/2} (x/2)^j / j!  (k = 6:
//           exp(-x/2) (1 + x/2 + x^2/8));
//   k odd:  P(X > x) = erfc(sqrt(x/2)) + sqrt(2x/pi) exp(-x/2)
//           sum_{j < (k-1)/2} x^j / (1 3 5 ... (2j+1))  (k = 3: the first term).
inline double chi2_survival(double x, int k) {
  const bool odd = k % 2 == 1;
  double term = odd ? std::sqrt(2 * x / std::numbers::pi) : 1.0, sum = 0.0;
  for (int j = 0; j < k / 2; ++j) {
    sum += term;
    term *= odd ? x / (2 * j + 3) : x / 2 / (j + 1);
  }
  return (odd ? std::erfc(std::sqrt(x / 2)) : 0.0) + std::exp(-x / 2) * sum;
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
