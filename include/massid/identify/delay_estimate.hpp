// What a fit did about the lag of the wrench stream behind the joint stream
// (delay.hpp): a value type of its own so that IdentifySummary can hold it.
#pragma once

#include <array>
#include <vector>

namespace massid {

struct DelayEstimate {
  bool applied = false;    // a delay was given or estimated (the params file records it)
  bool estimated = false;  // estimated from the data (else given)
  double value = 0.0;      // s, positive when the wrench arrives late
  double std = 0.0;        // s; 0 when given
  // Every fit of the scan: delay (s) and chi^2 of its residuals with the noise
  // of the fit at delay 0 (for the report's delay scan).
  std::vector<std::array<double, 2>> scan;
};

}  // namespace massid
