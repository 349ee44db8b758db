// Error types. Each carries the CLI exit code that the spec assigns to it.
#pragma once

#include <stdexcept>
#include <string>

namespace massid {

// Bad usage or bad input: a file that cannot be read, a malformed cell, an
// unsupported joint. The message names the file, line and column (or joint) at
// fault. CLI exit code 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The data cannot determine every base parameter. The message names the
// undetermined parameters and the poses that would determine them. Exit code 3.
class IdentifiabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace massid
