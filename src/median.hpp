// Private: the median of a sample (the mean of the two middle values when
// their number is even; 0 for none).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace massid::detail {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  if (v.size() % 2) return v[m];
  const double below = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m));
  return 0.5 * (below + v[m]);
}

}  // namespace massid::detail
