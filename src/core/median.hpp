// Private: the median of a sample as massid takes it everywhere: the element
// of rank n / 2 (for an even count the upper of the two middle values, as
// std::nth_element gives it); 0 for none. The streamed motion filter's
// histogram median (motion_csv_identify.cpp) is the same rank, so a streamed
// log and the same log in memory find the same time step.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace massid::detail {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace massid::detail
