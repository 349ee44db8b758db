#include "latency_histogram.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace massid {

int LatencyHistogram::bucket(std::int64_t ns) {
  const auto v = static_cast<std::uint64_t>(std::max<std::int64_t>(ns, 0));
  if (v < (1u << kExactBits)) return static_cast<int>(v);
  const int e = std::bit_width(v) - 1;  // 2^e <= v < 2^(e+1), e >= kExactBits
  if (e >= kMaxExponent) return kBuckets - 1;
  const int sub = static_cast<int>((v >> (e - kSubBits)) & ((1u << kSubBits) - 1));
  return (1 << kExactBits) + (e - kExactBits) * (1 << kSubBits) + sub;
}

double LatencyHistogram::upper_end(int b) {
  if (b < (1 << kExactBits)) return b;
  const int e = (b - (1 << kExactBits)) / (1 << kSubBits) + kExactBits;
  const int sub = (b - (1 << kExactBits)) % (1 << kSubBits);
  // Bucket [2^e + sub 2^(e-8), 2^e + (sub + 1) 2^(e-8)): its last integer.
  return std::ldexp(1.0, e) + std::ldexp(sub + 1.0, e - kSubBits) - 1.0;
}

void LatencyHistogram::record(std::int64_t ns) {
  ++counts_[bucket(ns)];
  ++count_;
  max_ = std::max(max_, ns);
}

double LatencyHistogram::percentile(double p) const {
  if (count_ == 0) return 0.0;
  const auto rank = std::clamp<std::int64_t>(
      static_cast<std::int64_t>(std::ceil(p * static_cast<double>(count_))), 1, count_);
  std::int64_t seen = 0;
  for (int b = 0; b < kBuckets; ++b) {
    seen += counts_[b];
    if (seen >= rank) return std::min(upper_end(b), static_cast<double>(max_));
  }
  return static_cast<double>(max_);
}

}  // namespace massid
