#include "argument_checks.hpp"

#include <string>

#include "massid/errors.hpp"

namespace massid::detail {

void throw_size_error(const char* function, const char* argument, Eigen::Index got,
                      Eigen::Index expected, const char* meaning) {
  throw ArgumentError(std::string("massid::") + function + ": " + argument + " has " +
                      std::to_string(got) + (got == 1 ? " entry" : " entries") + ", expected " +
                      std::to_string(expected) + " (" + meaning + ")");
}

void throw_index_error(const char* function, const char* argument, Eigen::Index i,
                       Eigen::Index count) {
  throw ArgumentError(std::string("massid::") + function + ": " + argument + " = " +
                      std::to_string(i) + " is outside [0, " + std::to_string(count) + ")");
}

}  // namespace massid::detail
