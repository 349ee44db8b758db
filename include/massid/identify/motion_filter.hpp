// Zero-phase low-pass filtering of a motion log, with the joint velocities and
// accelerations taken from the filter itself ("parallel filtering").
//
// Kernel. A Blackman-windowed sinc, symmetric in time (zero phase):
//   h(τ) = 2 fc sinc(2 fc τ) w(τ/T),   sinc(x) = sin(πx)/(πx),
//   w(u) = 0.42 + 0.5 cos(πu) + 0.08 cos(2πu)  on |u| ≤ 1 (0 outside),
// with T = kKernelSpan / fc = 3/fc (the window is 6 cutoff periods long; T is a
// zero of the sinc, so h, h', h'' all vanish continuously at ±T). To flatten
// the passband at 0 the smoothing kernel is s(τ) = h(τ) (α + β τ²) with α, β
// set from the discrete moments so that Σ s_k = 1 and Σ s_k τ_k² = 0
// (multiplying by τ² in time differentiates in frequency: the band is kept).
// The velocity and acceleration kernels are the analytic derivatives s', s''
// (product rule on sinc, window and taper; Taylor series of sinc near τ = 0),
// so the filtered velocity and acceleration are exactly the derivatives of the
// filtered position: responses S(f), i2πf S(f), −(2πf)² S(f), with
//   |S − 1| < 2e-4 for f ≤ fc/2 (< 1e-5 for f ≤ fc/10), S(fc) = 1/2,
//   |S| < 2e-4 for f ≥ 1.5 fc, < 2e-7 for f ≥ 5 fc.
// Sampled at the log's period Δ with H = floor(T/Δ), k = −H..H (index k + H),
// the discrete weights are
//   smooth_k = s(kΔ)Δ,  first_k = s'(kΔ)Δ,  second_k = s''(kΔ)Δ,
// and at centre sample i (a convolution: x_{i−k} pairs with weight k):
//   x_f(t_i) = Σ smooth_k x_{i−k},  ẋ_f(t_i) = Σ first_k x_{i−k},  ẍ_f(t_i) = Σ second_k x_{i−k}.
//
// Exactness. Weights are computed for k ≥ 0 and mirrored, so smooth and second
// are exactly even and first exactly odd. Each discrete kernel is then
// multiplied by a final taper (α' + β' τ_k²) solving two moment conditions, so
// that all three are exact on cubic polynomials in t to rounding. This corrects
// the sampling error of the sums (s'' is only C0 at ±T, the Blackman window
// being C1): β'T² ~ 1e-6 at rate = 100 fc, ≤ 1e-3 at rate = 20 fc.
//   smooth:  Σ s_k = 1,              Σ s_k (kΔ)² = 0
//   first:   Σ f_k (−kΔ) = 1,        Σ f_k (−kΔ)³ = 0     (Σ f_k = 0 by symmetry)
//   second:  Σ d_k (kΔ)²/2 = 1,      Σ d_k = 0
// (the sign: ẋ_f = Σ f_k x(t_i − kΔ), so a ramp x = t gives Σ f_k (−kΔ)).
//
// Parallel filtering. The same smoothing kernel is applied to every other
// per-row quantity of the regression (wrench, gravity, sensor motion, and any
// given velocities/accelerations): the regression y = Φ(q, q̇, q̈) θ then pairs
// quantities that passed the same filter, with the same delay (none).
//
// Edges. The first and last H samples, where the kernel would run off the data,
// are dropped. A log with a `block` column (sensor re-zeroed between blocks) is
// filtered block by block: the filter restarts at each change of block, and the
// edges of every block are dropped (a block must hold 2H+1 samples).
//
// Decimation. Only every D-th filtered sample is kept (the first kept is the
// first full-window centre of each block). The default D = floor(rate/(2 fc))
// strides the kept samples by about one correlation length of the filtered
// noise (a spectrum flat to fc has its first autocorrelation zero at 1/(2 fc)):
// the residuals of the kept rows are then nearly uncorrelated and
// residual-based standard deviations stay honest instead of shrinking by √D.
// For this kernel (noise bandwidth Σ s_k² / (2Δ) ≈ 0.90 fc) white noise kept at
// that stride has lag-one correlation ≈ 0.10, and the variance of a slowly
// varying fit is understated by ≈ 10 % (standard deviations by ≈ 5 %).
// Decimation also makes the filter cheaper: the kernels are evaluated only at
// kept samples.
//
// Time. The log must be sampled uniformly: t strictly increasing, every step
// within 0.1 % of the median step (kUniformTolerance); otherwise InputError
// names the line (and both lines for a repeated or decreasing t).
#pragma once

#include <string>
#include <vector>

#include "massid/core/samples.hpp"

namespace massid {

constexpr double kKernelSpan = 3.0;         // T = kKernelSpan / fc
constexpr double kUniformTolerance = 1e-3;  // relative deviation of a step from the period
constexpr double kMaxDefaultCutoff = 10.0;  // Hz

struct MotionFilterOptions {
  double cutoff = 0.0;  // Hz; 0: default_cutoff(rate)
  int decimation = 0;   // keep every D-th filtered sample; 0: default_decimation(rate, cutoff)
};

// min(10 Hz, rate/20): ten times below the Nyquist limit, so the kernel spans
// 121 samples or more and its transition band (fc/2 .. 1.5 fc) is well resolved, while
// 10 Hz passes the motion of a robot arm's identification trajectories
// (a few Hz) with their acceleration unchanged to ~1e-4.
double default_cutoff(double rate);
// max(1, floor(rate / (2 cutoff))).
int default_decimation(double rate, double cutoff);

// The three kernels for a sample period and cutoff (each of odd length 2H+1,
// index k = -H..H at k+H), weights including the factor Δ (see above).
struct FilterKernels {
  double dt = 0, cutoff = 0;
  int half_width = 0;
  std::vector<double> smooth, first, second;
  int size() const { return 2 * half_width + 1; }
};
// Throws InputError for dt <= 0, cutoff <= 0 or cutoff >= 1/(2 dt) (Nyquist).
FilterKernels make_kernels(double dt, double cutoff);
// 2 floor(kKernelSpan/(cutoff dt)) + 1: the samples one filtered output needs.
int kernel_samples(double dt, double cutoff);

// Kept rows (every `decimation`-th = D) whose filter windows share a sample:
// up to L = floor(2H / D) rows apart. Their noise (the wrench's through the
// smoothing kernel, the positions' through the derivative kernels) may
// correlate; beyond L it cannot (Samples::noise_lags). Returns
// min(L, kMaxNoiseLags): 12 at the default decimation; a decimation far below
// it (D = 1: L = 2H) would cost L factors per axis, and the correlation
// beyond kMaxNoiseLags rows is then left out (the std understated).
constexpr int kMaxNoiseLags = 24;
int correlated_rows(const FilterKernels& k, int decimation);

// The filter a log of sample period dt gets from `options` (defaults filled
// in): its kernels and decimation. InputError naming `source` and the lines
// first_line-last_line of the log for a cutoff that is not positive or at or
// above the Nyquist limit, or a negative decimation.
struct FilterPlan {
  FilterKernels kernels;
  int decimation = 1;
};
FilterPlan plan_filter(double dt, const MotionFilterOptions& options, const std::string& source,
                       int first_line, int last_line);

// Streaming form, constant memory: rows of `width` values pushed one at a time;
// columns [0, num_derived) are differentiated (positions -> value, velocity,
// acceleration), all `width` columns are smoothed. After a push, pop() yields
// the filtered row of the centre sample half_width rows back, when that sample
// is a kept one (every `decimation`-th). Call pop() after every push (a push
// while a row is ready throws std::logic_error). No allocation after
// construction.
class MotionFilter {
 public:
  MotionFilter(const FilterKernels& k, int width, int num_derived, int decimation);

  // Checks t against the previous row: increasing, step within
  // kUniformTolerance of k.dt (InputError "source:line: ..."). `line` is the
  // file line reported in errors and returned with the row.
  void push(const double* row, double t, int line);
  // True when an output row is ready: value[width], first[num_derived],
  // second[num_derived], and the t and line of its centre sample. Any pointer
  // may be null (that part is not written).
  bool pop(double* value, double* first, double* second, double* t, int* line);
  // Name used in error messages (default "data").
  void set_source(const std::string& source) { source_ = source; }
  // Forget all rows (a new block): the next push starts a new edge.
  void reset();

  const FilterKernels& kernels() const { return k_; }
  int width() const { return width_; }
  int num_derived() const { return nd_; }
  int decimation() const { return decimation_; }
  int half_width() const { return k_.half_width; }
  long long pushed() const { return count_; }  // rows since construction or reset()

 private:
  void compute();

  FilterKernels k_;
  int width_, nd_, decimation_, len_;
  std::vector<double> rev_smooth_, rev_first_, rev_second_;  // reversed: weight of window slot j
  std::vector<double> buffer_;  // 2 len_ rows of width_: each row written at slot s and s + len_
  std::vector<double> times_;   // len_ ring of t
  std::vector<int> lines_;      // len_ ring of line
  std::vector<double> out_;     // width_ + 2 nd_
  long long count_ = 0;
  double last_t_ = 0;
  int last_line_ = 0;
  bool ready_ = false;
  double out_t_ = 0;
  int out_line_ = 0;
  std::string source_ = "data";
};

// Whole-log form built on MotionFilter: returns a Samples with q (and
// q_upstream) smoothed, qd/qdd (and qd_upstream/qdd_upstream) derived,
// gravity, sensor_motion (if present) and wrench smoothed, time/line/block of
// the kept (centre) samples, edge samples dropped, decimated;
// derivatives_filtered = true. Requires samples.time. Velocities and
// accelerations that the input already has (qd present; qd_upstream present,
// or the sensor's motion with qd) are smoothed alike, not re-derived. The
// sample period is the median step of t. Blocks are filtered separately (see
// above). `used` receives the kernels. It runs the motion row pipeline
// (src/identify/motion_pipeline.hpp) over the samples: the code that filters
// a streamed file, so the two give the same rows.
// InputError (naming source:line) for: fewer than 2 samples, no t, repeated or
// decreasing t, non-uniform t or a gap, a log (block) shorter than the kernel,
// cutoff at or above the Nyquist limit, decimation < 0.
Samples filter_motion(const Samples& samples, const MotionFilterOptions& options,
                      FilterKernels* used = nullptr);

}  // namespace massid
