#include "core/argument_checks.hpp"

#include <fmt/format.h>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"

namespace massid::detail {

void throw_size_error(const char* function, const char* argument, Eigen::Index got,
                      Eigen::Index expected, const char* meaning) {
  throw ArgumentError(fmt::format("massid::{}: {} has {} {}, expected {} ({})", function, argument,
                                  got, got == 1 ? "entry" : "entries", expected, meaning));
}

void throw_index_error(const char* function, const char* argument, Eigen::Index i,
                       Eigen::Index count) {
  throw ArgumentError(
      fmt::format("massid::{}: {} = {} is outside [0, {})", function, argument, i, count));
}

void throw_empty_error(const char* function, const char* maker) {
  throw ArgumentError(
      fmt::format("massid::{}: the predictor is empty (make it with {})", function, maker));
}

void check_samples(const char* function, const Model& model, const Samples& s) {
  const Eigen::Index N = s.q.rows(), nj = model.num_joints(), nu = model.num_upstream_joints();
  const char* samples = "the samples, q's rows";
  check_size(function, "q columns", s.q.cols(), nj, "the model's joints");
  // An optional array: absent (0 columns, or empty), else of the full shape.
  const auto rows_cols = [&](const char* rows, const char* cols, const Eigen::MatrixXd& m,
                             Eigen::Index width, const char* meaning, bool required) {
    if (m.cols() == 0 && !required && width > 0) return;
    check_size(function, cols, m.cols(), width, meaning);
    if (width > 0) check_size(function, rows, m.rows(), N, samples);
  };
  rows_cols("gravity rows", "gravity columns", s.gravity, 3, "gx, gy, gz", true);
  rows_cols("wrench rows", "wrench columns", s.wrench, 6, "fx..mz", false);
  rows_cols("qd rows", "qd columns", s.qd, nj, "the model's joints", false);
  rows_cols("qdd rows", "qdd columns", s.qdd, nj, "the model's joints", false);
  rows_cols("q_upstream rows", "q_upstream columns", s.q_upstream, nu, "the upstream joints",
            false);
  rows_cols("qd_upstream rows", "qd_upstream columns", s.qd_upstream, nu, "the upstream joints",
            false);
  rows_cols("qdd_upstream rows", "qdd_upstream columns", s.qdd_upstream, nu, "the upstream joints",
            false);
  rows_cols("sensor_motion rows", "sensor_motion columns", s.sensor_motion, 9,
            "w, dw and a of the sensor frame", false);
  const auto optional = [&](const char* name, Eigen::Index size) {
    if (size != 0) check_size(function, name, size, N, samples);
  };
  optional("line", static_cast<Eigen::Index>(s.line.size()));
  optional("time", s.time.size());
  optional("block", static_cast<Eigen::Index>(s.block.size()));
}

}  // namespace massid::detail
