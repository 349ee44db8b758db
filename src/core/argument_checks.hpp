// Size checks of the public functions' arguments: one comparison, and on a
// mismatch an ArgumentError naming the function, the argument and both sizes,
// e.g. "massid::predict: q has 5 entries, expected 6 (the model's joints)".
#pragma once

#include <Eigen/Core>
#include <memory>

namespace massid::detail {

[[noreturn]] void throw_size_error(const char* function, const char* argument, Eigen::Index got,
                                   Eigen::Index expected, const char* meaning);

// got == expected, else ArgumentError. `meaning` says what `expected` counts.
inline void check_size(const char* function, const char* argument, Eigen::Index got,
                       Eigen::Index expected, const char* meaning) {
  if (got != expected) [[unlikely]]
    throw_size_error(function, argument, got, expected, meaning);
}

[[noreturn]] void throw_index_error(const char* function, const char* argument, Eigen::Index i,
                                    Eigen::Index count);

// 0 <= i < count, else ArgumentError.
inline void check_index(const char* function, const char* argument, Eigen::Index i,
                        Eigen::Index count) {
  if (i < 0 || i >= count) [[unlikely]]
    throw_index_error(function, argument, i, count);
}

[[noreturn]] void throw_empty_error(const char* function, const char* maker);

// A compiled predictor's plan, else ArgumentError ("the predictor is empty
// (make it with <maker>)"): a default-constructed predictor has none.
template <class Plan>
const Plan& checked_plan(const char* function, const std::shared_ptr<const Plan>& plan,
                         const char* maker) {
  if (!plan) [[unlikely]]
    throw_empty_error(function, maker);
  return *plan;
}

}  // namespace massid::detail

namespace massid {
struct Model;
struct Samples;
}  // namespace massid

namespace massid::detail {

// The arrays of `samples` agree with each other and with `model`: q [N x the
// model's joints]; gravity [N x 3]; each optional array (wrench [N x 6], qd and
// qdd [N x joints], the upstream ones [N x upstream joints], sensor_motion
// [N x 9], line, time, block [N]) absent or of that shape. Else ArgumentError
// naming the array, e.g. "massid::identify: gravity rows has 9 entries,
// expected 10 (the samples, q's rows)". (Motion samples without qd and qdd
// are samples at rest.)
void check_samples(const char* function, const Model& model, const Samples& samples);

}  // namespace massid::detail
