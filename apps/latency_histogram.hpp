// Latencies of a long run in constant memory: a log-linear histogram of
// nanoseconds (exact below 4096 ns, then 256 buckets per power of two, 0.4 %
// wide), from which the median, any percentile and the maximum are read.
// record() does not allocate.
#pragma once

#include <array>
#include <cstdint>

namespace massid {

class LatencyHistogram {
 public:
  void record(std::int64_t nanoseconds);
  std::int64_t count() const { return count_; }
  std::int64_t max() const { return max_; }
  // The smallest recorded latency (to the bucket's resolution) that at least
  // the fraction p (0..1] of the records do not exceed: the upper end of the
  // bucket that holds the ceil(p * count)-th smallest record. 0 when empty.
  double percentile(double p) const;

 private:
  static constexpr int kExactBits = 12;    // buckets of 1 ns below 2^12 ns
  static constexpr int kSubBits = 8;       // then 2^8 buckets per power of two
  static constexpr int kMaxExponent = 44;  // up to 2^44 ns (4.9 hours), beyond: the last bucket
  static constexpr int kBuckets = (1 << kExactBits) + (kMaxExponent - kExactBits) * (1 << kSubBits);
  static int bucket(std::int64_t ns);
  static double upper_end(int bucket);
  std::array<std::int64_t, kBuckets> counts_{};  // records per bucket
  std::int64_t count_ = 0, max_ = 0;
};

}  // namespace massid
