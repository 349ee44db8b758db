// Streaming identification: the same weighted least squares as identify()
// (estimation.hpp) from any number of samples in constant memory, from memory
// or from a memory-mapped CSV file parsed on several threads.
//
// What is kept. For each wrench axis a (fx ... mz) the triangular factor R_a of
// the unweighted, unscaled rows [A_a | y_a] of that axis (the TSQR idea: rows
// are buffered in chunks and folded into R_a by Householder reflections that
// touch only R_a's diagonal row and the chunk). The force axes' rows involve
// only M (and the axis' offset), the moment axes' rows only the moment
// unknowns (and the axis' offset), so R_a is over those columns only. Since
// R_a^T R_a = [A_a y_a]^T [A_a y_a] for any split of the rows, everything the
// dense solve needs follows from the six R_a:
//   - column norms (column scaling) and |y_a|^2: column norms of R_a;
//   - the weighted problem for any per-axis sigma: the QR of the stacked
//     [R_a S / sigma_a, R_a's y column / sigma_a] (a few dozen rows), so the
//     sigma re-estimation needs no second pass over the data;
//   - the residual sum of squares per axis: |R_a [x; -1]|^2;
//   - eq. 36: the singular values of the stacked moment axes' R_a;
//   - the identifiability rank: the stacked R_a have the same singular values
//     as the stacked regressor.
// Normal equations (A^T A) would square the condition number; this does not.
//
// The largest residual per axis needs the final estimate. accumulate_csv
// estimates the parameters from the first 2 MB of the file (a pilot), keeps the
// rows whose residual at that estimate is among the 64 largest per axis, and
// finish() recomputes those exactly: the maximum is proven when no other row
// can exceed it (its residual at the pilot estimate plus |a| |x - x_pilot|).
// Only when that fails (or StreamOptions::residual_max is set and the data
// came from elsewhere) is a second pass over the data made (residual_max_csv);
// without StreamOptions::residual_max the value is NaN.
//
// Motion (base.motion(), the full layout: BaseParameters::motion()). Every
// axis' rows then involve most mass unknowns: the force axes those whose
// column is a mass or first moment (an inertia has no force), the moment axes
// all but M (whose moment rows are zero), each with its axis' offset. Rows
// are computed one sample at a time in the sensor frame (equal to
// base_regressor's motion form to round-off) and folded by the same kernel;
// finish() reports eq. 36 as identify() does in motion (the column-scaled
// condition number of all rows), and the identifiability diagnosis sees the
// kept samples' velocities, accelerations and sensor motion.
//
// Motion logs from CSV (identify_motion_csv): the same columns and rules as
// read_motion_samples (JOINT_vel/JOINT_acc, wx..az, the joints above the
// sensor link, t, block). Without velocities, the zero-phase filter of
// motion_filter.hpp derives them in the stream: blocks of the file are parsed
// on threads, then each block is filtered on its own with the rows before it
// as a margin (MotionFilter restarted where filter_motion's decimation phase
// would have it), so the filtered rows are filter_motion's, bit for bit. What
// the whole log decides (the sample period: the median step of t; a fixed
// gravity; a moving sensor) is taken from the head of the file (the first
// 2 MB, or more until a full filter window) and checked during the stream:
// the period by counting steps below and at it, the other two by watching
// every filtered row (they can only change one way). When a check fails the
// stream is run again with what the whole file says (an exact median of the
// steps by radix selection over t, in constant memory).
//
// Determinism. Rows are cut into fixed blocks (a fixed number of rows in
// memory, a fixed number of bytes in a file, cut at line starts), each block is
// reduced on its own from an empty accumulator and the blocks are merged in
// file order, so results are bit-identical whatever the number of threads.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

struct StreamOptions {
  int threads = 0;                     // 0: std::thread::hardware_concurrency()
  std::size_t block_bytes = 4u << 20;  // CSV bytes per block (results depend on it, not on threads)
  int block_rows = 16384;              // rows per block when identifying from memory
  bool residual_max = true;            // second pass for IdentifySummary::residual_max
  std::size_t pilot_bytes = 2u << 20;  // the head of a CSV file read first (pilot estimate,
                                       // and a motion log's gravity and sensor motion)
  std::size_t keep_bytes = 48u << 20;  // motion logs: the prepared samples are kept for the
                                       // largest residual while they fit (216 B a sample for
                                       // six joints; a filtered log keeps one row in D)
};

// One sample in motion: arrays in Model::joints order; qd, qdd and
// sensor_motion may be null (zero: at rest, the sensor frame at rest).
// sensor_motion: wx wy wz, dwx dwy dwz, ax ay az (samples.hpp).
struct MotionRow {
  const double* q = nullptr;
  const double* qd = nullptr;
  const double* qdd = nullptr;
  const double* gravity = nullptr;  // [3] sensor frame
  const double* sensor_motion = nullptr;
  const double* wrench = nullptr;  // [6] fx..mz
  // Filtered rows (set_noise_lags): consecutive rows with equal `run`
  // are one run of the filter (its block), whose noise correlates.
  double run = 0.0;
};

namespace detail {
struct AccumulatorState;
}  // namespace detail

// Folds samples into the six per-axis triangular factors. Not thread-safe:
// give each thread its own and merge them in the order of their rows.
class IdentifyAccumulator {
 public:
  // model and base must outlive the accumulator.
  IdentifyAccumulator(const Model& model, const BaseParameters& base);
  ~IdentifyAccumulator();
  IdentifyAccumulator(IdentifyAccumulator&&) noexcept;
  IdentifyAccumulator& operator=(IdentifyAccumulator&&) noexcept;

  // One sample (with a static base only q, gravity and wrench are used; a
  // motion base takes null qd, qdd as at rest).
  void add(const MotionRow& row);
  // Every row of samples (which must have a wrench); their qd, qdd and sensor
  // motion with a motion base.
  void add(const Samples& samples);
  // Appends `later`'s rows after this one's (merging is exact in exact
  // arithmetic; in floating point the result depends on the order of merges).
  void merge(IdentifyAccumulator&& later);

  // Keep, from now on, the rows that could hold the largest residual, judged
  // against a provisional estimate (e.g. rough_estimate() of a prefix of the
  // data): finish() then reports residual_max without a second pass when the
  // kept rows prove it (the other rows' residuals at the estimate, plus how far
  // the final estimate moved, stay below it), else NaN. Every accumulator
  // merged into this one must track the same estimate. With `pilot` (whose
  // rough_estimate() `estimate` is): also bounds how much a row's residual
  // can move by its leverage in the pilot's metric,
  // |a (x - xhat)| <= |a R_p^-1| |R_p (x - xhat)| (R_p: the pilot's factor),
  // and keeps 1024 candidate rows per axis: with a pilot drawn from across
  // the data this proves the maximum where the plain bound cannot (motion,
  // where rows have many columns of different scales).
  void track_residuals(const Eigen::VectorXd& estimate, const IdentifyAccumulator* pilot = nullptr);
  // A new, empty accumulator for the same model and base, tracking the same
  // estimate (the partials of a stream: cheaper than track_residuals with a
  // pilot for each).
  IdentifyAccumulator empty_like() const;
  // An unweighted least-squares estimate of the rows so far (minimum norm when
  // they do not determine every unknown).
  Eigen::VectorXd rough_estimate() const;

  // Filtered rows (Samples::noise_lags; before the first add): the
  // covariance accounts for the correlation of the noise of rows up to `lags`
  // apart within a run (MotionRow::run), estimated from the residuals
  // (axis_least_squares.hpp, LagProducts). 0: independent rows. add(samples)
  // of a fresh accumulator takes the samples' own.
  void set_noise_lags(int lags);
  // Where the samples came from, for messages, and whether their gravity was
  // taken from the measured force (eq. 37) or from the joints above the
  // sensor link (IdentifySummary::gravity_from_upstream).
  void set_source(const std::string& source, bool gravity_from_force,
                  bool gravity_from_upstream = false);

  // The weighted least-squares solve of identify(), with the same checks and
  // errors (IdentifiabilityError). residual_max needs the final estimate: it
  // is NaN unless track_residuals proved it, and then a second pass over the
  // data (ResidualMax, residual_max_csv) finds it.
  IdentifySummary finish(const IdentifyOptions& options = {}) const;

 private:
  std::unique_ptr<detail::AccumulatorState> state_;
};

// The largest |measured - Y_b x| per axis over samples added to it. Samples
// are buffered and evaluated in batches (max() and merge() evaluate the ones
// still buffered), so one ResidualMax is not to be shared between threads.
class ResidualMax {
 public:
  ResidualMax(const Model& model, const BaseParameters& base, const Eigen::VectorXd& value);
  ~ResidualMax();
  ResidualMax(ResidualMax&&) noexcept;
  void add(const double* q, const double* gravity, const double* wrench);
  void add(const MotionRow& row);
  void merge(const ResidualMax& other);
  Eigen::Matrix<double, 6, 1> max() const;

 private:
  std::unique_ptr<detail::AccumulatorState> state_;  // samples are evaluated in batches
};

// identify(), streamed over samples already in memory (blocks on threads).
IdentifySummary identify_streaming(const Model& model, const BaseParameters& base,
                                   const Samples& samples, const IdentifyOptions& options = {},
                                   const StreamOptions& stream = {});

// Pass 1 over a CSV data file (same columns, rules and `read` options as
// read_samples with WrenchColumns::Required; InputError naming file:line:column): the
// accumulated factors. Constant memory: the file is memory-mapped and pages
// already parsed are released.
IdentifyAccumulator accumulate_csv(const Model& model, const BaseParameters& base,
                                   const std::string& path, const StreamOptions& stream = {},
                                   const SampleOptions& read = {});
// Pass 2: the largest residual per axis of the estimate `value`.
Eigen::Matrix<double, 6, 1> residual_max_csv(const Model& model, const BaseParameters& base,
                                             const std::string& path, const Eigen::VectorXd& value,
                                             const StreamOptions& stream = {},
                                             const SampleOptions& read = {});
// Both passes: the IdentifySummary of identify(model, base, read_samples(...)).
IdentifySummary identify_csv(const Model& model, const BaseParameters& base,
                             const std::string& path, const IdentifyOptions& options = {},
                             const StreamOptions& stream = {});

// ------------------------------------------------------------------ motion logs

// identify_motion_csv's result: what the in-memory path (read_motion_samples,
// motion_base_options, find_base_parameters, identify) gives, and how.
struct MotionIdentification {
  BaseParameters base;         // found for what the whole log is (motion_base_options)
  IdentifySummary summary;     // of identify(model, base, read_motion_samples(...))
  MotionDataReport report;     // rows, derived, kernels, decimation
  Samples head;                // the prepared samples of the head of the file (the pilot)
  int passes = 0;              // streamed passes (1 unless a head assumption failed)
  bool residual_pass = false;  // a further pass found residual_max
};

// Identification of a motion log (read_motion_samples' columns and rules,
// with WrenchColumns::Required), streamed in constant memory: the same
// results as the in-memory path to round-off, the same errors (InputError
// naming file:line:column; with several errors in a file, the first in the
// file). `offset`: estimate the six sensor offsets (BaseParameterOptions).
// Without StreamOptions::residual_max, residual_max may be NaN.
MotionIdentification identify_motion_csv(const Model& model, const std::string& path, bool offset,
                                         const IdentifyOptions& options = {},
                                         const MotionDataOptions& data = {},
                                         const StreamOptions& stream = {});

}  // namespace massid
