// Does a set of samples determine every unknown, and if not, which ones and
// what poses would? Used by identify (exit 3) and, later, by design.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"

namespace massid {

struct IdentifiabilityReport {
  int rank = 0;
  int unknowns = 0;
  std::vector<int> undetermined;            // unknowns involved in the null space
  bool tilt_would_help = false;             // more gravity directions would determine them
  std::vector<std::string> joints_to_move;  // moving one of these would help
  // At most this many independent equations can the data's number of
  // samples give (random ones; `unknowns` when there are 2 p samples or more);
  // when below `unknowns` the count is the cause and samples_needed is the
  // fewest that can determine every unknown.
  int equations = 0;
  int samples_needed = 0;
  std::string message;      // the user-facing explanation with its fix, one short line
  std::vector<Hint> hints;  // the settings the fix names (joints to hold at their values)
  bool ok() const { return rank == unknowns; }
};

// A: stacked regressor of the samples (estimation.hpp). Relative tolerance on
// the singular values of the column-normalised A.
IdentifiabilityReport check_identifiability(const Model& model, const BaseParameters& base,
                                            const Samples& samples, const Eigen::MatrixXd& A,
                                            double tolerance);

}  // namespace massid
