// Distance in units in the last place between two doubles of the same sign
// (or zero): 0 for equal values, 1 for neighbours.
#pragma once

#include <cstdint>
#include <cstring>

namespace massid::test {

inline std::int64_t ulps(double a, double b) {
  std::int64_t ia, ib;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  if (ia < 0) ia = INT64_MIN - ia;
  if (ib < 0) ib = INT64_MIN - ib;
  return ia > ib ? ia - ib : ib - ia;
}

}  // namespace massid::test
