// Size checks of the public functions' arguments: one comparison, and on a
// mismatch an ArgumentError naming the function, the argument and both sizes,
// e.g. "massid::predict: q has 5 entries, expected 6 (the model's joints)".
#pragma once

#include <Eigen/Core>

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

}  // namespace massid::detail
